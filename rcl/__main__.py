"""`python3 -m rcl`: the same as the `rcl` command."""
import sys

from rcl.cli import main

sys.exit(main())
