"""``python -m reports``: build the verification report and the reproducible paper."""
import gc
import os
import sys

# A short-lived process: Python's cyclic garbage collector stays off from before the build's
# dependencies load (their imports allocate most of the heap) to the exit, so that no collection
# walks everything the build allocated (:func:`reports.cli.cyclic_gc_paused` says why that is safe).
gc.disable()

from reports.cli import main  # noqa: E402

status = main()
# Every output is written and closed by now, and the messages are flushed below: the process ends
# without the interpreter's shutdown, which would still run one full collection (disabled or not:
# over the heap a build leaves, about 0.5 s of CPU) and then tear down every module and object one
# by one (about 0.03 s); the memory goes back to the system with the process either way. The exit
# handlers skipped are the libraries' own and have nothing to do after a build (logging's flush with
# no handlers, Pillow's and matplotlib's caches, sympy's line-cache entries).
sys.stdout.flush()
sys.stderr.flush()
os._exit(status)
