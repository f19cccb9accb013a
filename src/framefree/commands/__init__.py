"""Subcommands of the ``framefree`` CLI, one module per area; each exposes ``register(group)``."""
