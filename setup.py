"""Packaging beyond what pyproject.toml can say: the examples ship inside the package.

The teaching examples live in the repository's top-level ``examples/`` folder (where a
reader of the repository looks for them) and are installed as ``puckboard.examples``, so
``puckboard examples`` can list and run them after a plain ``pip install puckboard``, as
py_trees installs its demos. Everything else is configured in pyproject.toml.
"""

from setuptools import find_packages, setup

setup(
    packages=[*find_packages(include=["puckboard", "puckboard.*"]), "puckboard.examples"],
    package_dir={"puckboard.examples": "examples"},
)
