"""``python -m shapegen``: the same as the ``shapegen`` command."""

import sys

if __name__ == "__main__":
    try:
        from shapegen.cli import main
    except KeyboardInterrupt:  # Ctrl-C while the command itself is being imported
        sys.stderr.write("shapegen: interrupted\n")
        raise SystemExit(130) from None
    raise SystemExit(main())
