"""Draw docs/sensors.md's two figures and print the numbers the page quotes:

- docs/images/sensors_waves.png: an IMU, a pressure sensor and a DVL on the BlueROV2 Heavy holding station in
  the bundled waves scenario (bluerov2_heavy_alpha5_waves), their records against the truth computed here from
  the run's states (the mount's lever arm written out);
- docs/images/sensors_allan.png: the Allan deviation of a six-hour static gyro record (uvms.sensors.Imu on a
  vehicle at rest) with the datasheet lines N / sqrt(tau), 0.664 B and K sqrt(tau / 3) (IEEE Std 952).

Run from the checkout:  python tools/sensor_figures.py  (about a minute).
"""

import tempfile
from pathlib import Path

import numpy as np
import yaml
from matplotlib.figure import Figure

import uvms
from uvms.plots import save_figure
from uvms.sensors import FLICKER_FLOOR, Imu, NoiseDensity, Truth, allan_deviation
from uvms.sensors.allan import cluster_sizes
from uvms.sensors.noise import flicker_variances, gauss_markov_avar
from uvms.sim.scenario import load_scenario, resolve_scenario_path, run_scenario

IMAGES = Path(__file__).resolve().parent.parent / "docs" / "images"

SENSORS = {   # the docs/sensors.md example: every mount on the vehicle, in its body axes (forward-right-down)
    "imu": {"kind": "imu", "rate": 100, "mount": {"offset": [0.1, 0.0, -0.05]},
            "gyro": {"white": 2.0e-4, "bias_instability": 2.0e-4}, "accel": {"white": 5.0e-3}, "seed": 1},
    "depth": {"kind": "pressure", "rate": 10, "mount": {"offset": [-0.2, 0.0, 0.0]}, "noise": 50.0,
              "resolution": 20.0},
    "dvl": {"kind": "dvl", "rate": 5, "mount": {"offset": [0.0, 0.0, 0.15]}, "water_depth": 20.0,
            "max_altitude": 50.0, "dropout": 0.1, "noise": 0.005},
}


def rows_of(result, times) -> np.ndarray:
    """Indices of the run's rows at a sensor's sample times."""
    return np.searchsorted(np.round(result.time * 1e9), np.round(np.asarray(times) * 1e9))


def waves_figure() -> None:
    data = yaml.safe_load(resolve_scenario_path("bluerov2_heavy_alpha5_waves").read_text())
    data["sensors"] = SENSORS
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "sensed_waves.yaml"
        path.write_text(yaml.safe_dump(data, sort_keys=False))
        result = run_scenario(load_scenario(path))
    imu, depth, dvl = (result.sensors[k] for k in ("imu", "depth", "dvl"))
    g = rows_of(result, imu.time)
    truth_q = result.nu[g, 1]                                    # pitch rate: the mount has the body's axes
    d = rows_of(result, depth.time)
    r_p = np.array(SENSORS["depth"]["mount"]["offset"])
    R = result.rotations()[d]                                    # body to world
    truth_depth = result.position[d, 2] + (R @ r_p)[:, 2]        # ned: depth = z of the mount, surface at 0
    b = rows_of(result, dvl.time)
    r_d = np.array(SENSORS["dvl"]["mount"]["offset"])
    omega, v = result.nu[b, :3], result.nu[b, 3:]
    truth_ground = v + np.cross(omega, r_d)                      # velocity over ground at the mount

    fig = Figure(figsize=(8.0, 7.0), layout="constrained")
    ax = fig.subplots(3, 1, sharex=True)
    ax[0].plot(imu.time, imu["gyro_y"], lw=0.6, color="0.6", label="IMU gyro_y (100 Hz)")
    ax[0].plot(result.time[g], truth_q, lw=1.2, color="C0", label="true pitch rate q")
    ax[0].set_ylabel("rate [rad/s]")
    ax[1].plot(depth.time, depth["depth"], ".", ms=3, color="0.5", label="depth from pressure (10 Hz, 20 Pa steps)")
    ax[1].plot(result.time[d], truth_depth, lw=1.2, color="C1", label="true depth of the mount")
    ax[1].set_ylabel("depth [m]")
    ax[1].invert_yaxis()
    valid = dvl["bottom_valid"] > 0
    ax[2].plot(dvl.time[valid], dvl["bottom_x"][valid], "o", ms=3, color="C2", label="DVL bottom track x")
    ax[2].plot(dvl.time[~valid], np.zeros((~valid).sum()), "x", color="C3", label="dropout (NaN, no bag message)")
    ax[2].plot(result.time[b], truth_ground[:, 0], lw=1.2, color="C2", alpha=0.6, label="true over ground")
    ax[2].plot(dvl.time, dvl["water_x"], "s", ms=3, color="C4", label="DVL water track x")
    ax[2].set_ylabel("surge at mount [m/s]")
    ax[2].set_ylim(-0.4, 0.1)
    ax[2].set_xlabel("t [s]")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=7, loc="lower right" if a is ax[2] else "upper right", ncol=2)
    fig.suptitle("bluerov2_heavy_alpha5_waves with an IMU, a pressure sensor and a DVL", fontsize=10)
    save_figure(fig, IMAGES / "sensors_waves.png", dpi=90)
    print(f"waves: {len(result.time)} rows; gyro_y - q: std {np.std(imu['gyro_y'] - truth_q):.3g} rad/s; "
          f"depth error std {np.std(depth['depth'] - truth_depth) * 1000:.3g} mm; "
          f"bottom valid {valid.sum()} of {valid.size}; "
          f"bottom - truth std {np.nanstd(dvl['bottom_x'][valid] - truth_ground[valid, 0]) * 1000:.3g} mm/s")


def allan_figure() -> None:
    rate, hours = 100.0, 6.0
    N, B, K = 3.0e-5, 4.0e-5, 2.0e-6            # rad/s/sqrt(Hz), rad/s, rad/s^2/sqrt(Hz)
    gyro = NoiseDensity(white=N, bias_instability=B, band=(1.0, 1.0e5), random_walk=K)
    n = int(rate * hours * 3600)
    t = np.arange(n) / rate
    at_rest = Truth(time=t, position=np.zeros((n, 3)), rotation=np.broadcast_to(np.eye(3), (n, 3, 3)),
                    nu=np.zeros((n, 6)), nu_dot=np.zeros((n, 6)), q=np.zeros((n, 0)),
                    gravity=np.array([0.0, 0.0, 9.81]))
    record = Imu(rate=rate, gyro=gyro, seed=7).measure(at_rest)
    samples = np.column_stack([record[f"gyro_{a}"] for a in "xyz"])
    tau, sigma = allan_deviation(samples, rate, cluster_sizes(n, max_fraction=0.1))   # >= 10 clusters
    floor = FLICKER_FLOOR * B

    fig = Figure(figsize=(7.0, 4.6), layout="constrained")
    ax = fig.subplots()
    for i, a in enumerate("xyz"):
        ax.loglog(tau, sigma[:, i], lw=1.0, color=f"C{i}", label=f"gyro_{a}, 6 h at 100 Hz")
    ax.loglog(tau, N / np.sqrt(tau), "k--", lw=0.8, label=f"N / sqrt(tau), N = {N:g} rad/s/sqrt(Hz)")
    ax.loglog(tau, np.full_like(tau, floor), "k:", lw=1.0, label=f"0.664 B, B = {B:g} rad/s")
    ax.loglog(tau, K * np.sqrt(tau / 3.0), "k-.", lw=0.8, label=f"K sqrt(tau / 3), K = {K:g} rad/s^2/sqrt(Hz)")
    T, s2 = flicker_variances(B, gyro.band)
    total = np.sqrt(N ** 2 / tau + sum(gauss_markov_avar(tau, v, Tj) for v, Tj in zip(s2, T)) + K ** 2 * tau / 3.0)
    ax.loglog(tau, total, color="0.4", lw=2.5, alpha=0.4, label="closed form of the model (sum of the three)")
    ax.set_xlabel("cluster time tau [s]")
    ax.set_ylabel("Allan deviation [rad/s]")
    ax.set_ylim(1e-6, 1e-3)
    ax.grid(which="both", alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title("Allan deviation of a static gyro (overlapping, IEEE Std 952)", fontsize=10)
    save_figure(fig, IMAGES / "sensors_allan.png", dpi=90)
    low, flat = tau <= 0.1, (tau >= 5.0) & (tau <= 200.0)
    mean = sigma.mean(axis=1)                                    # the three axes' mean
    slope = np.polyfit(np.log(tau[low]), np.log(mean[low]), 1)[0]
    print(f"allan: slope below 0.1 s {slope:.3f}; N read off there (sigma sqrt(tau)) / N = "
          f"{np.mean(mean[low] * np.sqrt(tau[low])) / N:.3f}; lowest point between 5 and 200 s / 0.664 B = "
          f"{mean[flat].min() / floor:.3f} (tau {tau[flat][np.argmin(mean[flat])]:.3g} s); per axis "
          f"{', '.join(f'{v:.3f}' for v in sigma[flat].min(axis=0) / floor)}; closed form there / 0.664 B = "
          f"{total[flat][np.argmin(mean[flat])] / floor:.3f}; at the longest tau {tau[-1]:.4g} s: measured / "
          f"closed form {mean[-1] / total[-1]:.3f}")


if __name__ == "__main__":
    allan_figure()
    waves_figure()
