"""puckboard's teaching examples, installed as ``puckboard.examples``.

List them with ``puckboard examples`` and run one with ``puckboard examples run NAME``; in
a clone of the repository, ``python examples/NAME.py`` does the same.
"""
