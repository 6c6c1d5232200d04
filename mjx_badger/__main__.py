"""Entry point of `python -m mjx_badger`."""

import sys

from mjx_badger.cli import main

sys.exit(main())
