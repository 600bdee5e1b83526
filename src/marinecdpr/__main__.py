import sys

from marinecdpr.cli.app import main

sys.exit(main())
