"""Which pip extra of puckboard installs which optional package.

Optional packages are imported only where they are used. When one is missing, the
message must say which extra to install: the name Python reports (``zmq``, ``PIL``) is
often neither the package to install (pyzmq, Pillow) nor the extra that brings it
(``coppeliasim``, ``viz``), and a bare ``No module named 'rich'`` leaves a student
guessing. One table here keeps every such message in step with the extras of
``pyproject.toml`` (a test compares the two).
"""

from __future__ import annotations

__all__ = ["EXTRA_OF_MODULE", "extra_for", "install_command", "missing_package_message"]

#: Top-level import name → the extra of ``pyproject.toml`` that installs it.
EXTRA_OF_MODULE: dict[str, str] = {
    "zmq": "coppeliasim",
    "cbor2": "coppeliasim",
    "coppeliasim_zmqremoteapi_client": "coppeliasim",
    "serial": "real",
    "matplotlib": "viz",
    "PIL": "viz",
    "imageio": "viz",
    "pydot": "viz",
    "imageio_ffmpeg": "video",
    "rich": "cli",
    "aiohttp": "web",
    "irsim": "compare",
    "dask": "dask",
    "distributed": "dask",
    "pyarrow": "dask",
    "optuna": "tune",
    "statsmodels": "analysis",
    "mkdocs": "docs",
    "mkdocstrings": "docs",
}


def install_command(extra: str) -> str:
    """The command that installs ``extra``, quoted so that shells leave the brackets alone."""
    return f"pip install 'puckboard[{extra}]'"


def _top_module(exc: ImportError) -> str | None:
    """The top-level package the failed import asked for (``rich`` for ``rich.console``):
    that is what gets installed, whichever submodule was imported first."""
    return exc.name.partition(".")[0] if exc.name else None


def extra_for(exc: ImportError) -> str | None:
    """The extra that provides the module ``exc`` could not import, if it is one of ours."""
    module = _top_module(exc)
    return EXTRA_OF_MODULE.get(module) if module else None


def missing_package_message(what: str, exc: ImportError, extra: str | None = None) -> str:
    """``"<what> needs a missing package: zmq (install it with: pip install
    'puckboard[coppeliasim]')"``: one line naming the module and the extra to install.

    ``extra`` overrides the table (a backend registered with its own extra); without
    either, the line still names the module, so it is never worse than Python's own.
    """
    extra = extra or extra_for(exc)
    module = _top_module(exc) or (str(exc).strip().splitlines() or [type(exc).__name__])[0]
    hint = f" (install it with: {install_command(extra)})" if extra else ""
    return f"{what} needs a missing package: {module}{hint}"
