"""Built-in effects. Plugins: they use only the public host API."""
