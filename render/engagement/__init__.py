"""Engagements over time: Monte Carlo runs of a drone, birds and false alarms through a site's sensors into a tracker.

``sensors`` (each sensor's looks: line of sight, field of regard, Pd, measurements, false alarms and
clutter), ``tracker`` (Stone Soup's Kalman filter, association and an M-of-N initiator), ``simulate``
(one run, and the metrics over runs), ``spec`` (the ``csuas engage`` spec, pydantic).
"""
