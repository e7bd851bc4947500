import os
import sys

# The module is built into build/ by scripts/build.sh; tests may also run from elsewhere.
_build = os.path.join(os.path.dirname(__file__), "..", "..", "build")
if os.path.isdir(_build) and os.path.abspath(_build) not in sys.path:
    sys.path.insert(0, os.path.abspath(_build))
