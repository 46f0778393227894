"""``python -m granum`` is the ``granum`` command."""

import sys

from granum.cli import main

sys.exit(main())
