"""Frozen-app entry point: the same command line, the GUI when started without arguments."""

import sys

from wakeline.app.cli import main

if __name__ == "__main__":
    sys.exit(main())
