import os
import sys

# Import the package from the source tree even without devel/setup.bash sourced.
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "src"))
