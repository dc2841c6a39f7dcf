"""Worked solutions a student can follow (issue 11): ``python -m solver explain``.

* :func:`explain` builds the content (:mod:`.content`) once, from the scene's
  system at its state (:mod:`.build`);
* :func:`render` writes it as text, Markdown, HTML or LaTeX (:mod:`.render`);
* :func:`rank_points` is the point advisor (:mod:`.advisor`);
* :mod:`solver.display` holds the display forms built from structure.
"""
from .advisor import Candidate, rank_points
from .build import explain
from .render import FORMATS, render

__all__ = ["explain", "render", "rank_points", "Candidate", "FORMATS"]
