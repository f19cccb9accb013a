"""Views of a running recognizer (they consume its trace and events; never part of it)."""
