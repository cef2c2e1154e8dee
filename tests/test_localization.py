"""Monte Carlo localization (vwg/robot/localization.hpp): the likelihood field against hand-computed values,
the filter's motion model, weights and resampling against their definitions, convergence from a wrong start on
a real map, determinism by seed, the world-file key, and runs whose believed poses it corrects."""

from __future__ import annotations

import dataclasses
import math
import re
import statistics
import struct
from pathlib import Path

import numpy as np
import pytest

import vwg
import vwg._core as _core
from vwg.errors import WorldFileError
from vwg.robot.case_study import CaseStudy
from vwg.robot.world_file import Localization
from vwg.trial import random_task

SETTINGS = _core.LocalizationSettings()


def one_wall_cell(resolution: float = 0.05) -> _core.OccupancyGrid:
    """A 100 × 100 grid of 0.05 m, free but for the cell (50, 50), whose centre is (2.525, 2.525)."""
    data = np.zeros((100, 100), dtype=np.int8)
    data[50, 50] = 100
    return _core.OccupancyGrid(data, resolution, (0.0, 0.0, 0.0))


@pytest.mark.parametrize(("d", "pz"), [(0.0, 0.956250), (0.1, 0.844622), (0.2, 0.582454), (0.5, 0.047990)])
def test_the_likelihood_field_at_hand_computed_distances(d, pz):
    # pz = 0.95·exp(−d²/(2·0.2²)) + 0.05/8 (z_hit, σ_hit, z_rand over an 8 m laser): worked out by hand.
    field = _core.LikelihoodField(one_wall_cell(), SETTINGS, 8.0)
    x, y = 2.525 + d, 2.525  # along the row from the occupied cell's centre (cell centres are 0.05 apart)
    assert field.distance(x, y) == pytest.approx(d, abs=1e-6)
    assert field.pz(x, y) == pytest.approx(pz, abs=1e-6)


def test_the_field_is_capped_at_max_dist_and_off_the_map():
    field = _core.LikelihoodField(one_wall_cell(), SETTINGS, 8.0)
    assert field.distance(0.1, 0.1) == pytest.approx(2.0)  # 3.4 m from the cell: capped
    assert field.distance(-3.0, 1.0) == pytest.approx(2.0)  # off the map
    assert field.pz(-3.0, 1.0) == pytest.approx(0.95 * math.exp(-4.0 / 0.08) + 0.05 / 8)


def test_the_effective_size_of_weights_a_half_a_quarter_and_two_eighths():
    f = _core.ParticleFilter(SETTINGS.replace(particles=4))
    f.particles = np.array([[0, 0, 0, 0.5], [1, 0, 0, 0.25], [2, 0, 0, 0.125], [3, 0, 0, 0.125]], dtype=float)
    assert f.effective_size() == pytest.approx(1 / (0.25 + 0.0625 + 2 * 0.015625))  # 2.909...


@pytest.mark.parametrize("seed", range(8))
def test_low_variance_resampling_draws_each_particle_floor_or_ceil_of_n_times_its_weight(seed):
    # The property of systematic (low-variance) resampling: particle i is drawn ⌊N·w⌋ or ⌈N·w⌉ times.
    n = 50
    weights = np.random.default_rng(seed).dirichlet(np.ones(n))
    f = _core.ParticleFilter(SETTINGS.replace(particles=n))
    f.particles = np.column_stack([np.arange(n), np.zeros(n), np.zeros(n), weights])
    f.resample(seed)
    drawn = np.bincount(f.particles[:, 0].astype(int), minlength=n)
    assert drawn.sum() == n and np.all(f.particles[:, 3] == 1 / n)
    assert np.all(drawn >= np.floor(n * weights) - 1e-9) and np.all(drawn <= np.ceil(n * weights) + 1e-9)


def test_without_motion_noise_each_particle_makes_the_odometry_s_motion_in_its_own_frame():
    exact = SETTINGS.replace(particles=2, alpha_rot_rot=0.0, alpha_rot_trans=0.0, alpha_trans_trans=0.0,
                             alpha_trans_rot=0.0)
    f = _core.ParticleFilter(exact)
    f.particles = np.array([[0.0, 0.0, 0.0, 0.5], [5.0, 5.0, math.pi, 0.5]])
    # The odometry: 1 m forward while facing +y, then a quarter turn left.
    f.predict((1.0, 1.0, math.pi / 2), (1.0, 2.0, math.pi), seed=3)
    p = f.particles
    assert p[0, :3] == pytest.approx([1.0, 0.0, math.pi / 2], abs=1e-12)  # facing +x: 1 m along x, then turned
    assert p[1, :3] == pytest.approx([4.0, 5.0, -math.pi / 2], abs=1e-12)  # facing −x: 1 m along −x


def test_the_motion_noise_is_centred_on_the_odometry_s_motion():
    f = _core.ParticleFilter(SETTINGS.replace(particles=4000, start_xy=0.0, start_angle=0.0))
    f.start((0.0, 0.0, 0.0), seed=1)
    f.predict((0.0, 0.0, 0.0), (0.5, 0.0, 0.0), seed=2)
    p = f.particles
    assert p[:, 0].mean() == pytest.approx(0.5, abs=0.01) and p[:, 1].mean() == pytest.approx(0.0, abs=0.01)
    # α3 = 0.2 on a 0.5 m drive: the drive's standard deviation is √(0.2·0.25) = 0.2236 m.
    assert p[:, 0].std() == pytest.approx(math.sqrt(0.2 * 0.25), rel=0.1)


def office_scan(pose, angles, raycaster):
    return raycaster.scan(pose, angles, 8.0)


def test_the_filter_converges_on_the_office_from_a_wrong_start():
    office = vwg.robot.load_robot_world("office")
    field = _core.LikelihoodField(office.grid, SETTINGS, 8.0)
    raycaster = _core.GridRaycaster(office.grid)
    angles = np.linspace(-math.pi, math.pi, 360, endpoint=False)
    # The robot drives east along the corridor (y = 9) from x = 2; the filter starts 0.3 m and 0.1 rad off,
    # its particles spread 0.3 m and 0.15 rad, and is told the (exact) odometry of each 0.2 m step.
    f = _core.ParticleFilter(SETTINGS.replace(start_xy=0.3, start_angle=0.15))
    f.start((2.2, 9.2, 0.1), seed=7)
    errors = []
    for step in range(20):
        x0, x1 = 2.0 + 0.2 * step, 2.2 + 0.2 * step
        f.predict((x0, 9.0, 0.0), (x1, 9.0, 0.0), seed=100 + step)
        f.weigh(office_scan((x1, 9.0, 0.0), angles, raycaster), angles, 8.0, field)
        if f.effective_size() < 0.5 * SETTINGS.particles:
            f.resample(200 + step)
        ex, ey, ea = f.estimate()
        errors.append(math.hypot(ex - x1, ey - 9.0))
    assert errors[0] > 0.1  # it did start wrong
    assert max(errors[-5:]) < 0.1 and abs(ea) < 0.05, errors


def test_the_same_seed_gives_the_same_particles():
    def run(seed: int) -> np.ndarray:
        f = _core.ParticleFilter(SETTINGS)
        f.start((1.0, 2.0, 0.3), seed=seed)
        f.predict((0, 0, 0), (0.3, 0.1, 0.2), seed=seed + 1)
        return f.particles

    assert np.array_equal(run(4), run(4)) and not np.array_equal(run(4), run(5))


def test_settings_are_checked_by_field():
    with pytest.raises(vwg.SchemaError, match=r"localization\.particles: expected 1 to 100000 particles, got 0"):
        SETTINGS.replace(particles=0).check("localization")
    with pytest.raises(vwg.SchemaError, match=r"localization\.sigma_hit: expected a finite number > 0"):
        SETTINGS.replace(sigma_hit=0.0).check("localization")


def office_file(tmp_path, extra: str) -> Path:
    """The office world file with `extra` lines added, in tmp_path (its map named by its absolute path)."""
    office = vwg.robot.load_robot_world("office").path
    text = office.read_text(encoding="utf-8").replace("map: office/map.yaml",
                                                      f"map: {office.parent / 'office' / 'map.yaml'}")
    path = tmp_path / f"office_{len(list(tmp_path.iterdir()))}.yaml"
    path.write_text(text + extra, encoding="utf-8")
    return path


def test_the_world_file_key_is_checked_at_its_line(tmp_path):
    lines = vwg.robot.load_robot_world("office").path.read_text(encoding="utf-8").count("\n")
    for extra, message in [("localization: gps\n", r"localization: expected one of odometry, particles, got 'gps'"),
                           ("localization: {kind: particles, particles: 0}\n",
                            r"localization\.particles: expected 1 to 100000 particles"),
                           ("localization: {kind: particles, sigma: 1}\n", r"localization\.sigma: unknown key")]:
        with pytest.raises(WorldFileError, match=message) as caught:
            vwg.robot.load_robot_world(office_file(tmp_path, extra))
        assert f":{lines + 1}:" in str(caught.value)  # the line of the key
    loaded = vwg.robot.load_robot_world(office_file(tmp_path, "localization: {kind: particles, particles: 100}\n"))
    assert loaded.localization.kind == "particles" and loaded.localization.settings.particles == 100


def noisy_office(noise: float, localization: str) -> CaseStudy:
    office = vwg.robot.load_robot_world("office")
    world = dataclasses.replace(office, noise=_core.NoiseModel(odometry=noise),
                                localization=Localization.of(localization))
    return CaseStudy(world, "astar", goals={1: "meeting"}, seed=3, threads=1)


def test_odometry_localization_is_the_plain_run():
    with noisy_office(0.05, "odometry") as a:
        a.run(60)
        plain = CaseStudy(dataclasses.replace(a.world, localization=Localization()), "astar", goals={1: "meeting"},
                          seed=3, threads=1)
        with plain:
            plain.run(60)
            assert str(plain.engine.string) == str(a.engine.string)


def final_error(seed: int, kind: str) -> float:
    """The office's robot 1 sent to a room drawn from the seed, odometry drifting 0.05 per metre: the distance
    from where it believes it is to where it is (the simulator's truth) when the run ends."""
    world, goals = random_task(vwg.robot.load_robot_world("office"), 1, np.random.default_rng(seed))
    world = dataclasses.replace(world, noise=_core.NoiseModel(odometry=0.05), localization=Localization.of(kind))
    with CaseStudy(world, "astar", goals=goals, seed=seed, frames=3000, threads=1) as run:
        error = run.run().pose_error_m
    assert error is not None
    return error


@pytest.mark.slow
def test_with_particles_the_robots_end_nearer_where_they_believe_they_are():
    # The held-out check, on seeds of its own: the median final pose error with particles at most
    # 0.15 m and at most a third of odometry's alone.
    seeds = range(20, 26)
    odometry = statistics.median(final_error(seed, "odometry") for seed in seeds)
    particles = statistics.median(final_error(seed, "particles") for seed in seeds)
    assert particles <= 0.15 and particles <= odometry / 3, (particles, odometry)


@pytest.mark.slow
def test_a_run_with_particles_resumes_as_it_went_on(tmp_path):
    # The filters' particles and random streams and the lasers' last scans are in the state: the frames after
    # a resume are those of the run that went on.
    world = vwg.load(office_file(tmp_path, "noise: {odometry: 0.05}\nlocalization: particles\n"))
    with vwg.start(world, vwg.RunOptions(frames=40, goals=["meeting"], allow_unreached=True)) as run:
        run.execute()
        saved = run.save_state()
    with vwg.start(world, vwg.RunOptions(frames=80, goals=["meeting"], allow_unreached=True)) as whole:
        whole.execute()
        expected = str(whole.engine.string)
    with vwg.resume(saved, vwg.RunOptions(frames=40, allow_unreached=True)) as again:
        again.execute()
        assert again.engine.frame == 80 and str(again.engine.string) == expected


def test_a_localization_state_cut_forged_or_garbled_is_refused_naming_it(tmp_path):
    from test_state_hostile import cpp_items, replaced

    world = vwg.load(office_file(tmp_path, "localization: {kind: particles, particles: 50}\n"))
    with vwg.start(world, vwg.RunOptions(frames=20, goals=["meeting"], allow_unreached=True, threads=1)) as run:
        run.execute()
        data = run.save_state()
    index = 0  # the first generator, robot 1's: the robots' poses come first in the priority order
    (item,) = [i for i in cpp_items(data) if i[0] == "generators" and i[1] == index]
    _, _, where, blob = item
    # The random stream, the flag, four poses, the particles' count and 50 particles.
    stream = len(blob) - (1 + 4 * 24 + 8 + 50 * 32)
    assert 0 < stream < 100
    for cut in sorted({0, 1, 8, 9, len(blob) // 2, len(blob) - 1}):
        with pytest.raises(vwg.Error, match=re.escape(where)):
            vwg.resume(replaced(data, "generators", index, blob[:cut])).close()
    with pytest.raises(vwg.Error, match=re.escape(where)):
        vwg.resume(replaced(data, "generators", index, blob + b"\x00")).close()
    # The first particle's x made NaN (after the stream, the flag, four poses and the count).
    at = stream + 1 + 4 * 24 + 8
    forged = blob[:at] + struct.pack("<d", math.nan) + blob[at + 8:]
    with pytest.raises(vwg.Error, match="a particle that is not a finite pose"):
        vwg.resume(replaced(data, "generators", index, forged)).close()
    assert vwg.resume(data).engine.frame == 20  # the state itself resumes


def test_the_filters_give_the_same_frames_on_one_and_two_threads():
    # One generator a robot, run side by side: the frames are those of one thread, bit for bit.
    strings = []
    for threads in (1, 2):
        office = vwg.robot.load_robot_world("office")
        world = dataclasses.replace(office, noise=_core.NoiseModel(odometry=0.05),
                                    localization=Localization.of("particles"))
        with CaseStudy(world, "astar", goals={1: "kitchen", 2: "lab"}, seed=5, threads=threads) as run:
            run.run(80)
            strings.append(str(run.engine.string))
    assert strings[0] == strings[1]


@pytest.mark.parametrize(("bins", "needed"), [(1, 1), (2, 330), (10, 1085)])
def test_the_kld_bound_at_hand_computed_counts(bins, needed):
    # Fox 2003, eq. 12, with ε = 0.01 and z = 2.326, worked out by hand: k = 2 gives 50·(1 − 2/9 + √(2/9)·2.326)³
    # = 50 · 1.874266³ = 329.2; k = 10 gives 450 · 1.340805³ = 1084.7; one bin needs no more than one particle.
    assert _core.kld_bound(bins, 0.01, 2.326) == needed


def test_kld_sampling_draws_few_particles_where_they_agree_and_many_where_they_spread():
    settings = SETTINGS.replace(kld=True, particles=2000, min_particles=50)
    together = _core.ParticleFilter(settings)
    together.particles = np.tile([1.2, 3.4, 0.1, 1 / 2000], (2000, 1))  # one pose: one histogram bin
    together.resample(7)
    assert len(together.particles) == 50  # the least count
    spread = _core.ParticleFilter(settings)
    rng = np.random.default_rng(0)
    spread.particles = np.column_stack([rng.uniform(0, 20, 2000), rng.uniform(0, 20, 2000),
                                        rng.uniform(-3, 3, 2000), np.full(2000, 1 / 2000)])
    spread.resample(7)
    assert len(spread.particles) == 2000  # 1,600 xy bins × 35 heading bins: the bound passes the most
    assert np.allclose(spread.particles[:, 3], 1 / 2000)
    with pytest.raises(vwg.SchemaError, match=r"min_particles: expected 1 to particles \(2000\), got 0"):
        settings.replace(min_particles=0).check("localization")
    with pytest.raises(vwg.SchemaError, match=r"min_particles: expected 1 to particles \(2000\), got 3000"):
        settings.replace(min_particles=3000).check("localization")
    SETTINGS.replace(particles=50).check("localization")  # a fixed count needs no least one


def test_with_kld_sampling_the_filter_shrinks_once_it_has_converged():
    office = vwg.robot.load_robot_world("office")
    # amcl's bounds (100 to 5,000): the converged filter's particles fill a few dozen bins, which need ~2,000-3,000.
    settings = _core.LocalizationSettings(kld=True, particles=5000, min_particles=100)
    world = dataclasses.replace(office, noise=_core.NoiseModel(odometry=0.05),
                                localization=Localization("particles", settings))
    with CaseStudy(world, "astar", goals={1: "meeting"}, seed=3, threads=1) as run:
        summary = run.run(600)
        (robot1,) = [g for g in run.feedback if isinstance(g, _core.LocalizationGenerator) and g.robot == 1]
        assert 100 <= len(robot1.particles) < 4000
    assert summary.pose_error_m is not None and summary.pose_error_m < 0.15
