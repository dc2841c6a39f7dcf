"""``python -m reports``: build the verification report and the reproducible paper."""
import sys

from reports.cli import main

sys.exit(main())
