"""OSC out while recording, in real bpy: a receiver on loopback gets every frame, in order,
with the values the stored take has (the modes that apply, times their gains)."""

import bpy
import numpy as np
import pytest


@pytest.mark.parametrize("bundle", [True, False])
def test_recording_streams_every_frame_as_the_take_has_it(
    prepared, sub, make, bundle, osc_receiver
):
    ctx = prepared
    s = ctx.scene.voodoo
    s.target = make.flat_target(keyed=False)
    rx = osc_receiver()
    s.osc_send, s.osc_target, s.osc_bundle = True, f"127.0.0.1:{rx.port}", bundle
    s.modes[1].enabled = False  # not applied: not streamed
    s.modes[0].gain = 2.0
    assert bpy.ops.voodoo.track_clip() == {"FINISHED"}
    frames = [dict(rx.messages(d)) for d in rx.close()]
    storage = sub("operators.storage")
    stored = storage.stored_take(s.blob, s.last_take).take
    unit = sub("voodoo_addon.takes.rig").unit(storage.stored_blob(s.blob))
    osc_name = sub("voodoo_addon.stream").osc_name
    per_frame = len(s.modes) - 1 + 4  # frame, pose, the modes that apply, quality, view
    if not bundle:  # the same messages one datagram each: regroup them by frame
        assert len(rx.datagrams) == per_frame * len(stored)
        frames = [
            dict(m for d in rx.datagrams[i : i + per_frame] for m in rx.messages(d))
            for i in range(0, len(rx.datagrams), per_frame)
        ]
    assert len(frames) == len(stored)
    doll = f"/voodoo/{osc_name(s.blob.name)}"
    names = list(stored.param_names)
    assert [f[f"{doll}/frame"][0] for f in frames] == stored.frame_indices.tolist()
    for row, got in enumerate(frames):
        np.testing.assert_allclose(got[f"{doll}/pose"], stored.params[row, :4], rtol=1e-5)
        modes = {a.rsplit("/", 1)[-1]: v[0] for a, v in got.items() if "/mode/" in a}
        assert osc_name(s.modes[1].name) not in modes and len(modes) == len(s.modes) - 1
        first = s.modes[0]
        want = 2.0 * stored.params[row, names.index(first.name)] / unit
        assert modes[osc_name(first.name)] == pytest.approx(want, rel=1e-5, abs=1e-6)
        assert got[f"{doll}/quality"][0] == pytest.approx(stored.confidence[row], rel=1e-5)
        in_view = 0.0 if stored.lost[row] else stored.visible[row].mean()
        assert got[f"{doll}/view"][0] == pytest.approx(in_view, rel=1e-5)


@pytest.mark.parametrize("target", ["no port", "no-such-host.invalid:9000"])
def test_a_bad_osc_target_is_said_and_the_take_is_recorded(prepared, sub, make, target):
    ctx = prepared
    s = ctx.scene.voodoo
    s.target = make.flat_target(keyed=False)
    s.osc_send, s.osc_target = True, target
    rec = sub("operators.recorder").Recorder(ctx, live=False)
    while rec.step():
        pass
    info = rec.finish()
    assert info["frames"] == 20 and info["applied"]
    assert [n for n in info["notes"] if "recorded without streaming" in n] != []
