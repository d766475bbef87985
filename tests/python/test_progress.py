"""Progress callbacks and cancellation: reports arrive, False or an exception stops the work at once,
and a cancelled pack leaves nothing behind."""
import pytest

import lodforge
from conftest import SHARED

DRAGON = SHARED / "scan-dragon" / "dragon_vrip_res4.ply"


def test_progress_reports_fractions_and_stages(bunny):
    mesh = lodforge.read_mesh(str(bunny))
    calls = []
    chain = lodforge.build_lod_chain(mesh, levels=[0.5, 0.1], progress=lambda f, s: calls.append((f, s)))
    assert len(chain.levels) == 3
    assert len(calls) >= 5
    assert all(0.0 <= f <= 1.0 and isinstance(s, str) and s for f, s in calls)
    fractions = [f for f, _ in calls]
    assert fractions == sorted(fractions)  # one range over all levels: never backwards
    assert fractions[-1] > 0.9


def test_returning_false_cancels(bunny, tmp_path):
    mesh = lodforge.read_mesh(str(bunny))
    calls = []

    def stop_early(fraction, stage):
        calls.append(fraction)
        return fraction < 0.2

    with pytest.raises(lodforge.Cancelled) as e:
        lodforge.simplify(mesh, ratio=0.01, progress=stop_early)
    assert e.value.kind == "cancelled" and isinstance(e.value, lodforge.Error)
    # No report after the one that said stop: the work ended there.
    assert calls[-1] >= 0.2 and all(f < 0.2 for f in calls[:-1])
    # A cancelled pack leaves no directory (and nothing beside it).
    with pytest.raises(lodforge.Cancelled):
        lodforge.write_lod_pack(str(bunny), str(tmp_path / "pack"), preset="mobile", progress=lambda f, s: f < 0.5)
    assert list(tmp_path.iterdir()) == []


class Stop(Exception):
    pass


def test_an_exception_in_the_callback_cancels_and_is_raised(bunny, tmp_path):
    mesh = lodforge.read_mesh(str(bunny))
    calls = []

    def boom(fraction, stage):
        calls.append(fraction)
        if len(calls) == 3:
            raise Stop("enough")

    with pytest.raises(Stop, match="enough"):
        lodforge.build_lod_chain(mesh, levels=[0.5, 0.1, 0.02], progress=boom)
    assert len(calls) == 3
    calls.clear()
    with pytest.raises(Stop):
        lodforge.write_lod_pack(mesh, str(tmp_path / "pack"), source_path=str(bunny), progress=boom)
    assert not (tmp_path / "pack").exists()


def test_callbacks_from_worker_threads(tmp_path):
    # The octree computes nodes on two threads; each report takes the GIL from its own thread.
    stages = set()
    stats = lodforge.build_octree(str(DRAGON), str(tmp_path / "a.lfo"), max_triangles=1000, threads=2,
                                  progress=lambda f, s: stages.add(s))
    assert stats["leaves"] > 1 and stages
    with pytest.raises(lodforge.Cancelled):
        lodforge.build_octree(str(DRAGON), str(tmp_path / "b.lfo"), max_triangles=1000, threads=2,
                              progress=lambda f, s: False)
    assert not (tmp_path / "b.lfo").exists()
    assert [p.name for p in tmp_path.iterdir()] == ["a.lfo"]  # no temporary files left
