import os
import sys

# The module is built into build/ by scripts/build.sh (or $PURL_BUILD_DIR, as there).
_build = os.path.join(os.path.dirname(__file__), "..", "..", os.environ.get("PURL_BUILD_DIR", "build"))
if os.path.isdir(_build) and os.path.abspath(_build) not in sys.path:
    sys.path.insert(0, os.path.abspath(_build))
