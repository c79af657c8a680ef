"""Loading a Python source file that is not an installed module (a bench's scorer, a script without `.py`)."""
import importlib.machinery
import importlib.util
import os


def load_source(path, name=None):
    """Loads the Python source file at `path` as a module named `name` (default: the file's name without its
    extension) and returns it. The module is not added to `sys.modules`: each call gives a fresh module."""
    name = name or os.path.splitext(os.path.basename(path))[0]
    loader = importlib.machinery.SourceFileLoader(name, path)
    spec = importlib.util.spec_from_loader(name, loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def load_package_module(package, relative_path, name=None):
    """Loads `relative_path` inside the ROS package `package` (found by rospack, as `rospack find` does) with
    `load_source`, e.g. `load_package_module("greenhouse_rail_nav", "bench/uv_mission_scorer.py")`."""
    import rospkg
    return load_source(os.path.join(rospkg.RosPack().get_path(package), relative_path), name)
