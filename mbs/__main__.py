import sys

from mbs.cli import main

sys.exit(main())
