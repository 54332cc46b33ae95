"""The recording read by an independent reader: Python's mcap with mcap-protobuf-support,
decoding every message from the schemas the file carries (nothing of harmonav's)."""

import math

import pytest

import harmonav
from conftest import SCENARIOS

mcap_reader = pytest.importorskip("mcap.reader", reason="pip install mcap mcap-protobuf-support")
decoder = pytest.importorskip("mcap_protobuf.decoder", reason="pip install mcap-protobuf-support")


def test_every_message_decodes_from_the_files_own_schemas(tmp_path):
    res = harmonav.Scenario.load(SCENARIOS / "shapes" / "dynamic-small.toml").run(out=tmp_path)
    counts = {}
    grid = None
    with open(tmp_path / "run.mcap", "rb") as f:
        reader = mcap_reader.make_reader(f, decoder_factories=[decoder.DecoderFactory()])
        for schema, channel, message, decoded in reader.iter_decoded_messages():
            assert schema.encoding == "protobuf" and channel.message_encoding == "protobuf"
            counts[channel.topic] = counts.get(channel.topic, 0) + 1
            if channel.topic == "/theta":
                grid = decoded
            if channel.topic == "/harmonav/state":
                assert 0.0 <= decoded.theta <= 1.0 and decoded.k > 0
                assert decoded.damping == "governed"  # the default
    n = len(res.t)
    assert counts["/robot/pose"] == counts["/tf"] == counts["/harmonav/state"] == n
    assert counts["/scene"] >= 1 and counts["/log"] >= len(res.discoveries)
    assert grid is not None and grid.column_count > 0
    values = memoryview(grid.data).cast("f")
    assert len(values) == grid.column_count * (len(grid.data) // grid.row_stride)
    assert any(math.isnan(v) for v in values) and all(0.0 <= v <= 1.0 for v in values if not math.isnan(v))


def test_a_lidar_run_records_every_scan_and_the_perceived_shapes(tmp_path):
    """`[sensor] type = "lidar"`: every scan on /scan (foxglove.LaserScan, the beams as the
    navigator got them), the perceived shapes on /perceived at each event, and the summary's
    perception table with its three guarantees."""
    res = harmonav.Scenario.load(SCENARIOS / "lidar" / "paper-world.toml").run(out=tmp_path)
    s = res.summary
    p = s["perception"]
    assert s["reached"] and all(g["passed"] for g in s["guarantees"])
    names = {g["name"] for g in s["guarantees"]}
    assert {"perceived-covers-seen-truth", "perceived-shapes-only-grow", "scans-accepted"} <= names
    assert p["uncovered_points"] == 0 and p["seen_points"] > 1000 and p["events"] >= 1
    counts, beams = {}, set()
    with open(tmp_path / "run.mcap", "rb") as f:
        reader = mcap_reader.make_reader(f, decoder_factories=[decoder.DecoderFactory()])
        for schema, channel, message, decoded in reader.iter_decoded_messages():
            counts[channel.topic] = counts.get(channel.topic, 0) + 1
            if channel.topic == "/scan":
                assert schema.name == "foxglove.LaserScan"
                beams.add(len(decoded.ranges))
                assert decoded.end_angle > decoded.start_angle
            if channel.topic == "/perceived":
                assert len(decoded.entities) >= 1 and decoded.deletions
    assert counts["/scan"] == p["scans"] and counts["/perceived"] == p["events"]
    assert beams == {360}
    assert not s["discoveries"], "a lidar hands over no exact shape"


def test_a_floor_plan_run_records_its_walls_scans_and_states(tmp_path):
    """A floor plan's run.mcap (issue 26 in issue 25's maps): the true walls and the shrunk
    walls on /scene, one state per control period with Θ of the floor plan, every scan
    and each perceived update, read by the independent reader."""
    plan = harmonav.FloorPlan.load(SCENARIOS / "floorplans" / "lidar-room.toml")
    res = plan.run(model="kinematic", out=tmp_path)
    s, p = res.summary, res.summary["perception"]
    assert s["reached"] and all(g["passed"] for g in s["guarantees"])
    counts, scene, last = {}, None, None
    with open(tmp_path / "run.mcap", "rb") as f:
        reader = mcap_reader.make_reader(f, decoder_factories=[decoder.DecoderFactory()])
        for schema, channel, message, decoded in reader.iter_decoded_messages():
            counts[channel.topic] = counts.get(channel.topic, 0) + 1
            if channel.topic == "/scene":
                scene = decoded
            if channel.topic == "/harmonav/state":
                assert 0.0 <= decoded.theta < 1.0 and decoded.k > 0
                assert not decoded.HasField("energy") and decoded.damping == ""  # kinematic
                last = decoded
    assert counts["/robot/pose"] == counts["/tf"] == counts["/harmonav/state"] == s["commands"] + 1
    assert counts["/scan"] == p["scans"] and counts["/perceived"] == p["events"]
    assert counts["/theta"] == 1 + p["events"] and "/sensor/sector" not in counts
    ids = [e.id for e in scene.entities]
    assert ids[:2] == ["walls", "shrunk-walls"] and ids[-1] == "goal"
    assert last.t == pytest.approx(s["time_s"]) and math.hypot(
        last.x - s["goal"][0], last.y - s["goal"][1]
    ) == pytest.approx(s["final_distance"])
