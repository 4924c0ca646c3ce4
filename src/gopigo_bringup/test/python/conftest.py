import os
import sys

# Import the package from the source tree (works without a built devel space).
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "src"))
