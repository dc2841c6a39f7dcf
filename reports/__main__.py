"""``python -m reports``: build the verification report and the reproducible paper."""
import sys

from reports.make_report import main

sys.exit(main())
