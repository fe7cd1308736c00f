"""``python -m sso._cli``: the same as the ``sso`` command."""

import sys

from sso._cli import main

if __name__ == "__main__":
    sys.exit(main())
