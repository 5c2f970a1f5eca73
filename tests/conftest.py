import os
import signal
import tempfile

# The suite tests what Ctrl-C does.  A shell starts a background job (`pytest &` in a script, a CI runner's
# detached step) with SIGINT ignored (POSIX), Python keeps it ignored, and then `_thread.interrupt_main()`
# is a no-op and the commands the tests start inherit the ignored signal: the Ctrl-C tests would fail
# (the command runs to its end, status 0) for a reason that is not the code's.  Take SIGINT back.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)

os.environ.setdefault("MPLBACKEND", "Agg")
# JAX's strict promotion rules (as diffrax's tests): an implicit rank promotion (broadcasting arrays of
# different ranks) raises, and so does an implicit dtype promotion between JAX types (int32 + int64,
# float64 + int32; Python scalars stay weakly typed).  Set in the environment, they hold in the commands
# the tests run as subprocesses too.
os.environ["JAX_NUMPY_RANK_PROMOTION"] = "raise"
os.environ["JAX_NUMPY_DTYPE_PROMOTION"] = "strict"
# commands run as subprocesses keep their compiled kernels in this session's own cache, not the user's
# the commands' progress lines on a stderr that is not a terminal (validation/progress.py) are off: the
# tests read stderr for notes and errors; tests/test_progress_lines.py turns them on where it tests them
os.environ.setdefault("GEAR_RATTLE_PROGRESS_LINES", "0")
os.environ.setdefault("GEAR_RATTLE_JAX_CACHE", os.path.join(tempfile.mkdtemp(prefix="gear-rattle-test-"), "jax"))

from hypothesis import settings

from gear_rattle import use_cpu_devices  # imports JAX with float64

# the engine tests compare runs on one and on several XLA CPU devices
use_cpu_devices()

import jax  # noqa: E402

assert jax.config.jax_numpy_rank_promotion == "raise" and jax.config.jax_numpy_dtype_promotion == "strict"

settings.register_profile("ci", deadline=None, max_examples=40, derandomize=True)
settings.register_profile("long", deadline=None, max_examples=3000)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


import shutil  # noqa: E402
import subprocess  # noqa: E402

import pytest  # noqa: E402


@pytest.fixture
def full_disk(tmp_path):
    """A 64 KiB tmpfs at tmp_path/full (mounted where the test may: root with mount permitted), else the
    test is skipped with the reason (tests/test_safe_outputs.py, tests/test_suite_input.py)."""
    where = tmp_path / "full"
    where.mkdir()
    if not shutil.which("mount") or os.geteuid() != 0:
        pytest.skip("a full disk needs a tiny tmpfs: mount(8) as root is not available here")
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(where)], capture_output=True, text=True)
    if r.returncode != 0:
        pytest.skip(f"a full disk needs a tiny tmpfs, and mounting one was refused: {r.stderr.strip()}")
    try:
        yield where
    finally:
        subprocess.run(["umount", str(where)], capture_output=True)
        if os.path.ismount(where):
            subprocess.run(["umount", "-l", str(where)], capture_output=True)
