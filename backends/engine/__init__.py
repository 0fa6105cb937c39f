"""The open OpenISS engine: depth hand tracking and gesture recognition, shared by the named backends."""
