"""A detector in the loop (issue 28, section 4): a small torchvision detector trained on a csuas dataset,
its average precision by pixels on target and background beside the physics Pd of the same frames
(``csuas bench --only detector_loop``; docs/datasets.md, "A detector in the loop").

Importing this package never imports torch, torchvision or Mitsuba: ``training`` imports torch lazily,
``sets`` the renderer lazily.
"""
