"""``python -m shapegen``: the same as the ``shapegen`` command."""

from shapegen.cli import main

raise SystemExit(main())
