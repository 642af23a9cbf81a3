"""Base layer of csuas: errors, atomic file I/O, check records and plot styling.

Every other layer (core, defaults, drone_models, render, validation and the
command line) may import this package; it imports none of them.
"""
