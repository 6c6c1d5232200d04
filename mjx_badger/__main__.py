"""Entry point of `python -m mjx_badger`."""

import sys

from mjx_badger.cli.main import main

sys.exit(main())
