"""Writing derived equations out: C99 (printer + Jinja2 templates), CasADi functions and
textbook derivation printouts (text, LaTeX, Markdown).

Emitters derive nothing: they lay out what :mod:`symdyn.derive` produced.  Imports
:mod:`symdyn.model` and :mod:`symdyn.derive`, never :mod:`symdyn.check`.
"""
