"""Sub-commands of `voidcross`: one module per command, each with ``register(sub, common)``."""
