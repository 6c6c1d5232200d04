"""Entry point of `python -m mjx_badger`."""

import sys

from mjx_badger.cli.main import main

if __name__ == "__main__":  # not when a run's process (launch.py, spawned) imports it again
    sys.exit(main())
