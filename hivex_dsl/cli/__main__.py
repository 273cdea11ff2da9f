"""`python -m hivex_dsl.cli`: the `hivex` command."""

import sys

from . import main

sys.exit(main())
