"""``python -m uvms``: the command-line interface."""

import sys

from uvms.cli import main

sys.exit(main())
