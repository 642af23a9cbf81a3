"""Cost models against measured costs."""
