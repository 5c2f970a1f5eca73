"""``python -m gear_rattle``: the ``gear-rattle`` command line."""

import sys

from gear_rattle.validation.cli import main

if __name__ == "__main__":
    sys.exit(main())
