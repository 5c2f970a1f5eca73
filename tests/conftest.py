import os
import tempfile

os.environ.setdefault("MPLBACKEND", "Agg")
# commands run as subprocesses keep their compiled kernels in this session's own cache, not the user's
os.environ.setdefault("GEAR_RATTLE_JAX_CACHE", os.path.join(tempfile.mkdtemp(prefix="gear-rattle-test-"), "jax"))

from hypothesis import settings

from gear_rattle import use_cpu_devices  # imports JAX with float64

# the engine tests compare runs on one and on several XLA CPU devices
use_cpu_devices()

settings.register_profile("ci", deadline=None, max_examples=40, derandomize=True)
settings.register_profile("long", deadline=None, max_examples=3000)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
