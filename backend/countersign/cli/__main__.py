"""`python -m countersign.cli`."""

import sys

from . import main

sys.exit(main())
