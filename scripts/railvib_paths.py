"""Where the built railvib programs are, for the Python scripts and tests."""
import os
import shutil


def find_railvib_tool():
    """railvib_tool of the built workspace (devel space on CMAKE_PREFIX_PATH), else PATH; None if absent."""
    for prefix in os.environ.get("CMAKE_PREFIX_PATH", "").split(os.pathsep):
        candidate = os.path.join(prefix, "lib", "railvib", "railvib_tool")
        if prefix and os.access(candidate, os.X_OK):
            return candidate
    return shutil.which("railvib_tool")
