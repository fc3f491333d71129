"""The names of the old process-global counters and AMG registry still import, warn that
they are deprecated, and read the calling thread's most recent run: two threads see their
own runs."""

import dataclasses
import json
import threading

import numpy as np
import pytest

import fecontact.linalg as linalg
import fecontact.time as fetime
from fecontact import run
from fecontact.errors import InputError
from fecontact.testing import case
from fecontact.time import StepStats, simulate

OLD_KEYS = {  # the keys of the dicts of the process-global counters
    # (and the line search's count added since: updates taken within W's round-off)
    (fetime, "NEWTON"): {
        "iterations",
        "line_search_cuts",
        "shifted_directions",
        "roundoff_accepts",
    },
    (fetime, "FOLLOW_UPS"): {"steps", "shortened"},
    (fetime, "RELEASES"): {"steps"},
    (linalg, "ITERATIVE"): {
        "solves",
        "diagonal",
        "iterations",
        "setups",
        "fallbacks",
        "setup_seconds",
        "seconds",
    },
    (linalg, "SPARSE_FACTORIZATIONS"): {"count", "seconds"},
}


def _read(module, name):
    with pytest.warns(DeprecationWarning, match=name):
        return getattr(module, name)


def _simulate(name, t_end, **parameters):
    """The stats of a run of the case ``name`` up to ``t_end`` (s), and its model."""
    sim = case(name).build(**parameters)
    stats = StepStats()
    for _ in simulate(sim.model, sim.dt, t_end, sim.options, q0=sim.q0, v0=sim.v0, stats=stats):
        pass
    return stats, sim.model


def _old_counts(stats):
    """What each old name must read after the run that counted into ``stats``."""
    asdict = dataclasses.asdict
    return {
        "NEWTON": asdict(stats.newton),
        "FOLLOW_UPS": asdict(stats.follow_ups),
        "RELEASES": {"steps": stats.releases},
        "ITERATIVE": asdict(stats.iterative),
        "SPARSE_FACTORIZATIONS": asdict(stats.factorizations),
    }


def test_old_names_import_warn_and_keep_their_keys():
    for (module, name), keys in OLD_KEYS.items():
        assert name in module.__all__
        with pytest.warns(DeprecationWarning, match=name):
            exec(f"from {module.__name__} import {name}", {})
        view = _read(module, name)
        assert set(view) == keys
        with pytest.raises(TypeError):  # read-only
            view["steps"] = 1
    assert "set_near_null_space" in linalg.__all__
    with pytest.raises(AttributeError):
        _ = fetime.NO_SUCH_COUNTER


def test_old_names_hold_the_numbers_of_the_last_run():
    stats, _ = _simulate("flexible_pendulum", 0.05)
    expected = _old_counts(stats)
    assert expected["NEWTON"]["iterations"] > 0  # (a comparison of zeros would show nothing)
    for module, name in OLD_KEYS:
        assert dict(_read(module, name)) == expected[name]


def test_old_names_read_what_run_reports(tmp_path):
    # a sparse solid model: its factorizations are counted
    sim = case("two_disks").build(refinements=2).replace(t_end=0.0003)
    run(sim, tmp_path, frames=False, checkpoint_every=0)
    summary = json.loads((tmp_path / "summary.json").read_text())
    factorizations = dict(_read(linalg, "SPARSE_FACTORIZATIONS"))
    assert factorizations["count"] == summary["sparse_factorizations"]["count"] > 0
    assert dict(_read(fetime, "NEWTON")) == summary["smooth_newton"]


def test_two_threads_see_their_own_runs():
    runs = {
        "pendulum": ("flexible_pendulum", 0.03, {}),
        "disks": ("two_disks", 0.0003, {"refinements": 2}),
    }
    both_done = threading.Barrier(len(runs))
    seen, counted = {}, {}
    # the names read once, here (warnings are caught per process, not per thread): each view
    # reads the run of the thread that reads it
    newton, factorizations = _read(fetime, "NEWTON"), _read(linalg, "SPARSE_FACTORIZATIONS")

    def one(key):
        name, t_end, parameters = runs[key]
        stats, _ = _simulate(name, t_end, **parameters)
        both_done.wait(timeout=600)  # the other thread's run has ended too
        seen[key] = dict(newton), dict(factorizations)
        counted[key] = _old_counts(stats)

    threads = [threading.Thread(target=one, args=(key,)) for key in runs]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    for key in runs:
        newton, factorizations = seen[key]
        assert newton == counted[key]["NEWTON"]
        assert factorizations == counted[key]["SPARSE_FACTORIZATIONS"]
    # the runs' counts differ (the disks' sparse factorizations, the pendulum's dense ones)
    assert seen["pendulum"][0] != seen["disks"][0]
    assert seen["disks"][1]["count"] > seen["pendulum"][1]["count"] == 0


def test_set_near_null_space_replaces_the_model_modes_in_this_thread_only():
    sim = case("two_disks").build(refinements=1)
    n = sim.model.n_free
    modes = np.zeros((n, 2))
    modes[0::2, 0] = modes[1::2, 1] = 1.0  # the two translations (x, y dofs alternate)
    with pytest.warns(DeprecationWarning, match="set_near_null_space"):
        linalg.set_near_null_space(modes)
    _, model = _simulate("two_disks", 0.0001, refinements=1)
    assert model.solver.modes is modes

    other = {}

    def elsewhere():
        _, model = _simulate("two_disks", 0.0001, refinements=1)
        other["modes"] = model.solver.modes, model.rigid_modes

    thread = threading.Thread(target=elsewhere)
    thread.start()
    thread.join()
    used, own = other["modes"]
    assert used is own  # another thread's runs keep their model's rigid motions
    with pytest.raises(InputError, match="modes"):
        linalg.set_near_null_space([[1.0, 0.0]])
