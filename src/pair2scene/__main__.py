import sys

from pair2scene.cli import main

sys.exit(main())
