"""The voidcross report: the thesis's tables and figures regenerated from a sweep database,
beside the thesis's own values, as one static HTML page and one Markdown file.

``build_report(db, out, fem_dir=None, cad_dir=None, limits=None)``; the thesis's
Tables 4.4-4.9 are transcribed in ``thesis_data/`` (one CSV per table, naming it).
"""

from .build import build_report

__all__ = ["build_report"]
