"""``python -m sso.cli``: the same as the ``sso`` command."""

import sys

from sso.cli import main

if __name__ == "__main__":
    sys.exit(main())
