"""Tailor: interactive assembly and animation of 3D garments.

The heavy lifting lives in the native extension ``tailor._tailor`` (Rust); this package
re-exports it and adds the command line (``python -m tailor``).
"""

from tailor._tailor import *  # noqa: F401,F403
from tailor._tailor import __version__  # noqa: F401
