"""The strand readers (read_strand_targets) and the USC-HairSalon .data format against
independent references: a .data file packed by hand with struct from its published layout
(docs/file-formats.md), and `ringlet groom` / `ringlet convert` (the C++ command)."""
import struct

import numpy as np
import pytest

import ringlet
from conftest import cli_error


def pack_data(strands):
    """The .data layout: int32 strand count; per strand int32 vertex count, float32 xyz."""
    out = struct.pack("<i", len(strands))
    for s in strands:
        out += struct.pack("<i", len(s))
        for p in s:
            out += struct.pack("<3f", *p)
    return out


STRANDS = [[(0.0, 0.1, 0.2), (0.0, 0.05, 0.2), (0.01, 0.0, 0.21)],
           [(0.5, 0.25, -0.125)],  # one vertex: no hair at this root, skipped
           [(-0.1, 0.3, 0.0), (-0.1, 0.2, 0.0)]]


def test_data_decoded_as_packed_by_hand_and_encoded_back():
    data = pack_data(STRANDS)
    z_up = ringlet.decode_usc_data(data, up="z")
    assert list(z_up.point_counts) == [3, 2]  # the 1-vertex strand is skipped
    expected = np.array([p for s in STRANDS if len(s) > 1 for p in s], dtype=np.float32)
    assert np.array_equal(z_up.points, expected)
    # y up (the database's convention): (x, y, z) -> (x, -z, y), exact for float32 values.
    y_up = ringlet.decode_usc_data(data)
    assert np.array_equal(y_up.points, np.stack([expected[:, 0], -expected[:, 2],
                                                 expected[:, 1]], axis=1))
    # Written back (without the empty strand): the bytes packed by hand.
    kept = pack_data([s for s in STRANDS if len(s) > 1])
    assert ringlet.encode_usc_data(z_up, up="z") == kept
    assert ringlet.encode_usc_data(y_up) == kept


def test_truncated_and_hostile_data_raise_one_line():
    data = pack_data(STRANDS)
    with pytest.raises(ringlet.Error) as e:
        ringlet.decode_usc_data(data[:-3])
    assert "\n" not in str(e.value) and "strand" in str(e.value)
    # A header announcing 2^31 - 1 strands in a few bytes fails before any allocation.
    with pytest.raises(ringlet.Error):
        ringlet.decode_usc_data(struct.pack("<i", 2**31 - 1) + b"\0" * 8)
    with pytest.raises(ringlet.Error):
        ringlet.decode_usc_data(data, up="x")


def test_reading_the_commands_files_gives_the_groom_back(cli, tmp_path, small_style):
    path, _ = small_style
    out = tmp_path / "out"
    cli("groom", path, "-o", out, "--quiet", "--formats", "hair,usda,obj")
    reference = ringlet.read_hair_file(str(out / "strands.hair"))
    for name in ("strands.hair", "strands.usda", "strands.obj"):
        read = ringlet.read_strand_targets(str(out / name))
        assert np.array_equal(read.point_counts, reference.point_counts), name
        assert np.array_equal(read.points, reference.points), name
    # The module's .data file equals the one `ringlet convert` writes from the same groom.
    ringlet.write_usc_data(str(tmp_path / "mine.data"), reference)
    cli("convert", out / "strands.hair", tmp_path / "cli.data", "--out-up-axis", "y", "--quiet")
    assert (tmp_path / "mine.data").read_bytes() == (tmp_path / "cli.data").read_bytes()
    with pytest.raises(ringlet.Error):  # no silent overwrite
        ringlet.write_usc_data(str(tmp_path / "mine.data"), reference)


def test_bad_target_file_raises_the_commands_message(cli, tmp_path):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 0 0 0\nl 1 2\n")  # a repeated point: no tangent
    with pytest.raises(ringlet.Error) as e:
        ringlet.read_strand_targets(str(bad))
    message = cli_error(cli("convert", bad, tmp_path / "x.hair", check=False))
    assert str(e.value) == message
