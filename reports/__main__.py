"""``python -m reports``: build the verification report and the reproducible paper."""
import gc
import sys

# A short-lived process: Python's cyclic garbage collector stays off from before the build's
# dependencies load (their imports allocate most of the heap) to the exit, so that no collection
# walks everything the build allocated (:func:`reports.cli.cyclic_gc_paused` says why that is safe).
gc.disable()

from reports.cli import main  # noqa: E402

status = main()
# The interpreter still runs one full collection as it shuts down, disabled or not: over the heap a
# build leaves that took about 0.5 s of CPU. Frozen objects are not traversed (the memory goes back
# to the system with the process); every output is written and closed by now.
gc.freeze()
sys.exit(status)
