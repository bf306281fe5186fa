"""Where the built railvib programs are, for the Python scripts and tests."""
import os
import shutil


def find_railvib_tool():
    """railvib_tool: the one RAILVIB_TOOL names, else the built workspace's (devel space on
    CMAKE_PREFIX_PATH), else PATH's; None if absent. (The sanitizer workspace builds no tool: its node
    fuzz is given the regular build's through RAILVIB_TOOL.)"""
    if os.environ.get("RAILVIB_TOOL"):
        return os.environ["RAILVIB_TOOL"]
    for prefix in os.environ.get("CMAKE_PREFIX_PATH", "").split(os.pathsep):
        candidate = os.path.join(prefix, "lib", "railvib", "railvib_tool")
        if prefix and os.access(candidate, os.X_OK):
            return candidate
    return shutil.which("railvib_tool")


class OutputDirError(Exception):
    pass


def output_dir(path):
    """PATH as a directory for a command's outputs, created if needed; OutputDirError (the reason, no
    traceback) when it is a file or cannot be created."""
    import pathlib
    path = pathlib.Path(path)
    if path.exists() and not path.is_dir():
        raise OutputDirError(f"{path} exists and is not a directory (give a directory for the outputs)")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise OutputDirError(f"{path}: cannot create the output directory ({e.strerror})")
    if not os.access(path, os.W_OK):
        raise OutputDirError(f"{path}: the output directory is not writable")
    return path
