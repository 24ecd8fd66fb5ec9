"""``python -m puckboard`` is the same as the ``puckboard`` command."""

import sys

from .cli import main

sys.exit(main())
