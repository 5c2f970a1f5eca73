"""The small atlas grid of the atlas tests (tests/test_atlas.py, tests/test_atlas_store.py): the spec and
the same grid as ``gear-rattle atlas`` options, in 2 x 2 tiles."""

from gear_rattle.validation.atlas import AtlasSpec

# 4 x 3 grid through the paper's Fig. 4 scan: alpha = 2, 2.33, 2.67, 3 and r = 0.8, 0.85, 0.9
SMALL = AtlasSpec(
    alpha_lo=2.0, alpha_hi=3.0, n_alpha=4, r_lo=0.8, r_hi=0.9, n_r=3, transient=300, impacts=500, period_max=16
)
CLI_SMALL = [
    "atlas",
    "--alpha-lo",
    "2",
    "--alpha-hi",
    "3",
    "--n-alpha",
    "4",
    "--r-lo",
    "0.8",
    "--r-hi",
    "0.9",
    "--n-r",
    "3",
    "--transient",
    "300",
    "--impacts",
    "500",
    "--period-max",
    "16",
    "--tile",
    "2",
]
