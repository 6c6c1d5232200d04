"""TensorBoard event files: one run per seed, one scalar per finite metric value, begun afresh on resume."""

import struct

import numpy as np
from tensorboardX.proto import event_pb2

from mjx_badger.learning import tensorboard


def _scalars(folder) -> list:
    """(tag, step, value) of every scalar in a seed's event files (TFRecords: length, crc, event, crc)."""
    found = []
    for path in sorted(folder.glob("events.out.tfevents.*")):
        data = path.read_bytes()
        at = 0
        while at < len(data):
            (length,) = struct.unpack("<Q", data[at:at + 8])
            event = event_pb2.Event.FromString(data[at + 12:at + 12 + length])
            at += 12 + length + 4
            found += [(v.tag, event.step, v.simple_value) for v in event.summary.value]
    return found


def test_each_seed_gets_its_finite_scalars_at_the_chunks_step(tmp_path):
    out = tmp_path / "run.json"
    written = {"steps": [100], "metrics": {"train/falls": [[1.0, 2.0]]}}  # a resumed run's first chunk
    writer = tensorboard.Writer(out, [0, 1], written)
    writer.write({"train/falls": [3.0, 4.0], "train/critic_loss": [np.nan, 0.5], "eval/pair": [[1.0, 2.0], [3.0, 4.0]]},
                 200)
    writer.close()
    assert tensorboard.folder(out) == tmp_path / "run.tb"
    seed_0 = _scalars(tmp_path / "run.tb" / "seed_0")
    assert ("train/falls", 100, 1.0) in seed_0 and ("train/falls", 200, 3.0) in seed_0
    assert not any(tag == "train/critic_loss" for tag, _, _ in seed_0)  # NaN during warm-up: left out
    assert ("eval/pair/1", 200, 2.0) in seed_0  # a vector per seed: one scalar per entry
    assert ("train/critic_loss", 200, 0.5) in _scalars(tmp_path / "run.tb" / "seed_1")
    tensorboard.Writer(out, [0], {"steps": [], "metrics": {}}).close()  # a run begun again starts empty
    assert _scalars(tmp_path / "run.tb" / "seed_0") == [] and not (tmp_path / "run.tb" / "seed_1").exists()
