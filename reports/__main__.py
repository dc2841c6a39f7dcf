"""``python -m reports``: build the verification report and the reproducible paper."""
import gc
import sys

# A short-lived process: Python's cyclic garbage collector stays off from before the build's
# dependencies load (their imports allocate most of the heap) to the exit, so that no collection
# walks everything the build allocated (:func:`reports.cli.cyclic_gc_paused` says why that is safe).
gc.disable()

from reports.cli import main  # noqa: E402

sys.exit(main())
