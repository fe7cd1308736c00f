"""``python -m sso``: the ``sso`` command, for environments without its script."""

import sys

from sso._cli import main

if __name__ == "__main__":
    sys.exit(main())
