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
                assert decoded.damping in ("paper", "auto")
    n = len(res.t)
    assert counts["/robot/pose"] == counts["/tf"] == counts["/harmonav/state"] == n
    assert counts["/scene"] >= 1 and counts["/log"] >= len(res.discoveries)
    assert grid is not None and grid.column_count > 0
    values = memoryview(grid.data).cast("f")
    assert len(values) == grid.column_count * (len(grid.data) // grid.row_stride)
    assert any(math.isnan(v) for v in values) and all(0.0 <= v <= 1.0 for v in values if not math.isnan(v))
