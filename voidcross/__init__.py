"""voidcross: the command line and the end-to-end pipeline (cad -> fem -> sim -> report)."""

__version__ = "0.1.0"
