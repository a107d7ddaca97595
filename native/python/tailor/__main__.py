"""``python -m tailor``: see :mod:`tailor.cli`."""

import sys

from tailor.cli import main

sys.exit(main())
