# Finding the isotrace binary and checking that it is new enough.
import os
import re
import shutil
import subprocess

# The first release with spot lights and shaped (Blender) metaball elements.
MINIMUM_VERSION = (0, 2, 0)


class BinaryError(Exception):
    """A missing, broken or too old isotrace binary: one message for the user."""


def find_binary(preferred=""):
    """The binary: ISOTRACE_BINARY, else the add-on's preference, else PATH."""
    for candidate in (os.environ.get("ISOTRACE_BINARY", ""), preferred):
        if candidate:
            path = os.path.abspath(os.path.expanduser(candidate))
            if not (os.path.isfile(path) and os.access(path, os.X_OK)):
                raise BinaryError(f"isotrace binary not found or not executable: {path} "
                                  "(set it in the add-on's preferences or ISOTRACE_BINARY)")
            return path
    found = shutil.which("isotrace")
    if not found:
        raise BinaryError("isotrace binary not found: install isotrace, or set its path in the add-on's "
                          "preferences (Edit > Preferences > Add-ons > isotrace) or in ISOTRACE_BINARY")
    return found


def check_version(binary):
    """The binary's version as a tuple; BinaryError when it cannot run or is older than needed."""
    try:
        run = subprocess.run([binary, "--version"], capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise BinaryError(f"isotrace binary {binary} does not run: {e}") from e
    match = re.search(r"isotrace (\d+)\.(\d+)\.(\d+)", run.stdout + run.stderr)
    if run.returncode != 0 or not match:
        raise BinaryError(f"{binary} is not an isotrace binary (--version printed: {(run.stdout + run.stderr).strip()!r})")
    version = tuple(int(g) for g in match.groups())
    if version < MINIMUM_VERSION:
        need = ".".join(map(str, MINIMUM_VERSION))
        raise BinaryError(f"isotrace {'.'.join(map(str, version))} at {binary} is too old: this add-on needs {need} or newer")
    return version
