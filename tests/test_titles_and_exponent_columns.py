"""Results say what they are: ``bifurcation --lyapunov`` writes the exponents it draws to ``--output``,
and the figures' titles name every parameter (the swept one by its range)."""

import json
from types import SimpleNamespace

import numpy as np

from gear_rattle.core.params import Params
from gear_rattle.validation.cli import main
from gear_rattle.validation.dynamics.bifurcation import Diagram, DiagramLyapunov
from gear_rattle.validation.plots import branch_figure, diagram_figure, lyapunov_figure, velocity_series_figure
from gear_rattle.validation.plots.base import params_text
from gear_rattle.validation.plots.dynamics import diagram_lyapunov_figure
from gear_rattle.validation.plots.transients import basins_figure, uncertainty_figure

BASE = Params(3.0, 0.1, 0.1, 0.9)
NAMED = ("alpha=3", "beta=0.1", "gamma=0.1")


def _diagram() -> Diagram:
    values = np.array([0.8, 0.9])
    sdot = np.array([[1.0, np.nan], [2.0, 3.0]])
    return Diagram("r", values, sdot, np.ones((2, 2)), np.isfinite(sdot), "fixed", BASE, 10, 2)


def _lyapunov():
    return SimpleNamespace(
        values=np.array([0.8, 0.9]),
        lam=np.array([[-np.inf, -np.inf], [0.3, -1.0]]),
        lam_free=np.array([[-0.1, -0.5], [0.3, -1.0]]),
        n_stuck=np.array([4, 0]),
        n_steps=50,
    )


def _title(fig) -> str:
    return fig.axes[0].get_title()


def test_params_text_names_every_parameter_and_the_swept_range():
    assert params_text(BASE) == "alpha=3, beta=0.1, gamma=0.1, r=0.9"
    assert params_text(BASE, "r", np.linspace(0.6, 1.0, 5)) == "alpha=3, beta=0.1, gamma=0.1, r in [0.6, 1] (5 values)"


def test_titles_name_the_parameters():
    """The bifurcation title named the mode and the swept parameter only ('bifurcation diagram (fixed), r
    varied'); the time series' alpha and r only, Fig. 9 alpha only; lyapunov, orbit continue and Fig. 10 none."""
    d = _diagram()
    title = _title(diagram_figure(d, (d.values, _lyapunov().lam_free)))
    assert all(x in title for x in NAMED) and "r in [0.8, 0.9] (2 values)" in title
    title = _title(lyapunov_figure(d.values, _lyapunov().lam_free, "r", title=params_text(BASE, "r", d.values)))
    assert all(x in title for x in NAMED)
    ts = SimpleNamespace(n=np.arange(3), sdot_n=np.ones(3), k=np.arange(2), sdot_strobe=np.ones(2), params=BASE)
    assert all(x in _title(velocity_series_figure(ts)) for x in NAMED + ("r=0.9",))
    branch = SimpleNamespace(
        params=BASE,
        impacts=6,
        turns=1,
        folds=[],
        flips=[],
        arrays=lambda: {
            "mu": np.array([0.8, 0.9]),
            "sdot": np.ones(2),
            "stable": np.array([True, False]),
            "mult_re": np.ones((2, 2)),
            "mult_im": np.zeros((2, 2)),
        },
    )
    assert all(x in _title(branch_figure(branch, "r")) for x in NAMED + ("6-impact",))
    report = diagram_lyapunov_figure(DiagramLyapunov(d, _lyapunov()), "Fig. 4", [("r1", 0.85)])
    assert all(x in _title(report) for x in NAMED + ("Fig. 4", "r in [0.8, 0.9]"))  # had the range only
    fake = SimpleNamespace(
        params=BASE, ns=[], eps=np.logspace(-9, -3, 3), n_points=10, fits={}, nx=2, ny=2, delta=0.1, ic_mode="box"
    )
    assert all(x in _title(uncertainty_figure(fake)) for x in NAMED + ("r=0.9",))  # had no parameter
    assert all(x in basins_figure(fake)._suptitle.get_text() for x in NAMED + ("r=0.9",))  # had alpha only


def test_diagram_with_exponents_writes_them():
    """CSV: the exponents of each row's value in four more columns; NPZ/JSON: per value."""
    dl = DiagramLyapunov(_diagram(), _lyapunov())
    header, rows = dl.table()
    assert header == ["r", "n", "theta", "sdot", "lambda1", "lambda2", "lambda1_free", "lambda2_free"]
    assert rows[0][:2] == [0.8, 0] and rows[0][4:] == [-np.inf, -np.inf, -0.1, -0.5]
    assert [r[0] for r in rows] == [0.8, 0.9, 0.9] and rows[2][4:] == [0.3, -1.0, 0.3, -1.0]
    a = dl.arrays()
    assert np.array_equal(a["lambda1_free"], [-0.1, 0.3]) and a["lyapunov_impacts"] == 50 and a["alpha"] == 3.0


def test_bifurcation_lyapunov_output_has_the_exponent_columns(tmp_path, capsys):
    """``bifurcation --lyapunov N --output FILE`` wrote the diagram's points only (the old code's JSON had
    no lambda key); now the exponents drawn in panel b too."""
    out = tmp_path / "d.json"
    rc = main(
        [
            "bifurcation",
            "--values",
            "2",
            "--lo",
            "0.85",
            "--hi",
            "0.9",
            "--transient",
            "20",
            "--impacts",
            "3",
            "--lyapunov",
            "100",
            "--output",
            str(out),
            "--quiet",
        ]
    )
    capsys.readouterr()
    data = json.loads(out.read_text())
    assert rc == 0 and data["values"] == [0.85, 0.9]
    for key in ("lambda1", "lambda2", "lambda1_free", "lambda2_free"):
        assert len(data[key]) == 2 and all(isinstance(x, float) for x in data[key])
    assert data["lyapunov_impacts"] == 100 and data["lambda1_free"][1] > 0  # r = 0.9: Fig. 3's chaos
