"""One mechanism each: the run sizes of every analysis (:mod:`validation.profiles`) and the one figure
writer (:func:`validation.io.save_figure`, at one resolution for the report and the commands)."""

import argparse

import numpy as np
import pytest

from gear_rattle.validation import cliutil
from gear_rattle.validation.io import save_figure
from gear_rattle.validation.io.formats import FIGURE_DPI
from gear_rattle.validation.profiles import PROFILE_NAMES, PROFILES, get_profile


def test_every_part_is_read_by_the_one_get_profile():
    """Every part of both profiles is read the same way: a copy of a dict, a flag as it is."""
    assert PROFILE_NAMES == ("quick", "paper") and set(PROFILES["quick"]) == set(PROFILES["paper"])
    for profile in PROFILE_NAMES:
        for part, value in PROFILES[profile].items():
            got = get_profile(profile, part)
            assert got == value if not isinstance(value, dict) else got is not value and got.keys() == value.keys()
    assert get_profile("quick", "alt_ic", {"n": 30}) == {"n": 30}  # a None size takes a count
    assert get_profile("paper", "diagrams", {"transient": 0})["transient"] == 0


@pytest.mark.parametrize(
    "args,match",
    [
        (("quick", "fig4"), "part='fig4' is out of range"),
        (("quick", "confirm", {"n": 1}), "'confirm' is a flag"),
        (("quick", "basins", {"nx": 0}), r"sizes\['nx'\]=0 is out of range"),
        (("quick", "diagrams", {"keep": 2.5}), r"sizes\['keep'\]"),
        (("slow", "basins"), "profile='slow' is out of range"),
    ],
)
def test_bad_profile_requests_name_the_argument(args, match):
    with pytest.raises(ValueError, match=match):
        get_profile(*args)


def _png_size(path) -> tuple[int, int]:
    """Width and height in pixels from a PNG's IHDR chunk."""
    head = path.read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n" and head[12:16] == b"IHDR"
    return int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")


def _figure():
    from gear_rattle.validation.plots.base import subplots

    fig, ax = subplots(figsize=(2.0, 1.0))
    ax.plot(np.arange(3.0))
    return fig


def test_one_figure_writer_at_one_resolution(tmp_path):
    """The report's writer was at 110 dpi, the commands' --plot at 150 (simulate 110, atlas 130): now
    one writer, :data:`FIGURE_DPI` = 150, for both (a 2 x 1 inch figure is 300 x 150 pixels)."""
    fig = _figure()
    save_figure(fig, tmp_path / "a.png")
    cliutil.write_plot(argparse.Namespace(plot=str(tmp_path / "sub" / "b.png")), fig)
    assert FIGURE_DPI == 150 and not hasattr(cliutil, "save_figure")
    for name in ("a.png", "sub/b.png"):
        assert _png_size(tmp_path / name) == (300, 150)
