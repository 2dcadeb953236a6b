"""`python3 -m clsph ARGS...` runs the clsph command-line tool installed beside this package."""
import os
import shutil
import sys


def _tool():
    here = os.path.dirname(os.path.abspath(__file__))
    candidates = [os.environ.get("CLSPH_TOOL", "")]
    # Installed: PREFIX/lib/pythonX.Y/site-packages/clsph -> PREFIX/bin/clsph
    candidates.append(os.path.normpath(os.path.join(here, "..", "..", "..", "..", "bin", "clsph")))
    try:  # the build tree: written by CMake next to this file
        from . import _build_paths
        candidates.append(_build_paths.TOOL)
    except ImportError:
        pass
    candidates.append(shutil.which("clsph") or "")
    for c in candidates:
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return c
    return None


def main():
    tool = _tool()
    if tool is None:
        sys.stderr.write("python3 -m clsph: cannot find the clsph tool (install clsph, or set CLSPH_TOOL)\n")
        return 1
    os.execv(tool, [tool] + sys.argv[1:])


if __name__ == "__main__":
    sys.exit(main())
