import sys

from pendulab.cli import main

sys.exit(main())
