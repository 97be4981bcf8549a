"""hipsim's version, one place for the package, its outputs and its reports."""

__all__ = ["__version__"]

__version__ = "0.4.0"
