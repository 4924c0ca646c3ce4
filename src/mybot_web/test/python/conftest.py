import os
import sys

# The pure modules and the server need no ROS environment: import them from the source tree.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "src"))
