"""``uvms identify`` on logs that uvms made with noise added (motion-capture CSV files in the z-up convention,
encoders with offsets and signs): it recovers the parameters that made them within the uncertainties it
reports, keeps the held-out log out of the fit, and writes a fitted model file that loads."""

import numpy as np
import pytest

import uvms
from tests.replays.synthetic import write_log
from uvms.cli import main
from uvms.model.parameters import with_parameters


def test_identify_recovers_known_parameters_from_noisy_synthetic_logs(tmp_path, capsys):
    base = uvms.load_model("paper")
    truth_values = {"cob.z": float(base.cob[0, 2]) - 0.008, "cob.x": float(base.cob[0, 0]) + 0.003}
    truth = with_parameters(base, truth_values)
    truth_file = tmp_path / "truth.yaml"
    from importlib.resources import files

    truth_file.write_text((files("uvms") / "model" / "models" / "paper.yaml").read_text()
                          + f"\nidentified:\n  parameters: {{cob.z: {truth_values['cob.z']!r}, "
                            f"cob.x: {truth_values['cob.x']!r}}}\n")
    assert uvms.load_model(truth_file).cob[0, 2] == truth.cob[0, 2]
    logs = [write_log(tmp_path / f"log{k}", uvms.load_model(truth_file), log_frame="enu", seconds=6.0,
                      noise_deg=0.05, noise_m=0.001, seed=k, start_euler=(0.1 - 0.2 * k, 0.15, 0.3 * k),
                      name=f"trial{k}")[0] for k in range(3)]
    out = tmp_path / "fit.yaml"
    code = main(["identify", "paper", str(logs[0]), str(logs[1]), "--held-out", str(logs[2]),
                 "--fit", "cob.z,cob.x", "--signals", "roll,pitch", "-o", str(out)])
    assert code == 0
    fitted = uvms.load_model(out)
    record = __import__("yaml").safe_load(out.read_text())["identified"]["record"]
    assert record["held_out"] == ["trial2"] and record["fitted_on"] == ["trial0", "trial1"]
    for name, index in (("cob.z", fitted.cob[0, 2]), ("cob.x", fitted.cob[0, 0])):
        p = record["parameters"][name]
        assert abs(p["initial"] - truth_values[name]) > 20 * p["std"]             # the start was far off
        assert abs(index - truth_values[name]) <= 3.0 * p["std"], (name, index, truth_values[name], p["std"])
    held = next(s for s in record["scores"] if s["role"] == "held_out")
    assert held["pitch_rmse_deg_after"] < 0.2 * held["pitch_rmse_deg_before"]
    assert "fitted model written to" in capsys.readouterr().out


@pytest.mark.parametrize("arguments, message", [
    (["--fit", "cob.w"], "unknown parameter 'cob.w'"),
    (["--fit", "cob.z=2:1"], "lower < upper"),
    (["--fit", "cob.z", "--signals", "heading"], "unknown signal 'heading'"),
    (["--fit", "cob.z", "--max-evaluations", "0"], "--max-evaluations: expected a whole number >= 1, got 0"),
    (["--fit", "cob.z", "--threads", "-3"], "--threads: expected a whole number >= 1, got -3"),
    (["--fit", "cob.z", "--step", "0"], "--step: expected a positive, finite number [s], got 0.0"),
])
def test_bad_identify_options_exit_2_and_write_nothing(tmp_path, capsys, arguments, message):
    path, _ = write_log(tmp_path / "log", uvms.load_model("paper"), seconds=2.0)
    out = tmp_path / "fit.yaml"
    assert main(["identify", "paper", str(path), *arguments, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_a_fit_that_stops_early_or_at_a_bound_says_so_and_writes_its_best_point(tmp_path, capsys):
    """Issue 25, bad input: non-convergence is said (and recorded), the best point is written, and a parameter
    stopped at a bound is named, on stderr, beside the fitted file."""
    import yaml

    base = uvms.load_model("paper")
    path, _ = write_log(tmp_path / "log", with_parameters(base, {"cob.z": float(base.cob[0, 2]) - 0.008}),
                        seconds=3.0)
    out = tmp_path / "fit.yaml"
    bound = f"cob.z={float(base.cob[0, 2]) - 0.002}:{float(base.cob[0, 2]) + 0.01}"      # the truth lies below it
    code = main(["identify", "paper", str(path), "--fit", f"{bound},cob.x", "--max-evaluations", "20",
                 "-o", str(out)])
    assert code == 0
    err = capsys.readouterr().err
    record = yaml.safe_load(out.read_text())["identified"]["record"]
    assert record["at_bound"] == ["cob.z"] and "stopped at a bound: cob.z" in err
    assert uvms.load_model(out).cob[0, 2] == pytest.approx(float(base.cob[0, 2]) - 0.002, abs=1e-5)
    stopped = tmp_path / "stopped.yaml"
    assert main(["identify", "paper", str(path), "--fit", "cob.z", "--max-evaluations", "1",
                 "-o", str(stopped)]) == 0
    err = capsys.readouterr().err
    assert "the fit did not converge" in err and "the best point found was kept" in err
    assert yaml.safe_load(stopped.read_text())["identified"]["record"]["converged"] is False


def test_the_progress_bar_counts_evaluations_on_a_terminal_and_stays_quiet_elsewhere():
    """``uvms identify``'s progress bar (stderr, a terminal only): evaluations done of the most allowed, and the
    cost of the last one; nothing at all when stderr is not a terminal (a log file)."""
    import io

    from rich.console import Console

    from uvms.commands.identify import _Progress

    for terminal in (True, False):
        bar = _Progress(30)
        sink = io.StringIO()
        bar.console = Console(file=sink, force_terminal=terminal, width=120)
        with bar as progress:
            progress(7, 1234.5)
            if terminal:
                bar.bar.refresh()
        text = sink.getvalue()
        assert ("7/30 evaluations, cost 1234" in text) is terminal and (text == "") is not terminal
