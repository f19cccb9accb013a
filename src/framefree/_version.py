"""The version of framefree (one place, imported by the package and by the library file format)."""

__version__ = "0.1.0"
