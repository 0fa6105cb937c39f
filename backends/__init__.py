"""Built-in backends (gesture providers). Plugins: they use only the public host API."""
