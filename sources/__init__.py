"""Built-in depth sources (plugins: they use only the public host API)."""
