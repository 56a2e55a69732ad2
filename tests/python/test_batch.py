"""Datasets from Python (python/batch_bindings.cpp, python/ringlet/batch.py; docs/batch.md):
ringlet.BatchSpec, resolve_batch_item and run_batch_item against the `ringlet batch` command
(the same files, byte for byte; the same --plan), skipping done items, the manifest's line, and
the errors. The Dask engine with real processes: tests/dask/ (ctest python_dask)."""
import hashlib
import json
import pathlib

import pytest

import ringlet
import ringlet.batch

from conftest import EXAMPLES, cli_error


def spec_files(tmp_path):
    spec = json.loads((EXAMPLES / "batch" / "small.json").read_text())
    spec["count"] = 4
    spec["bases"] = [str(EXAMPLES / "hairstyles" / "wavy_mannequin.json"),
                     str(EXAMPLES / "hairstyles" / "curly_mannequin.json")]
    spec["outputs"]["images"] = {"width": 16, "height": 16, "samples_per_pixel": 1}
    path = tmp_path / "spec.json"
    path.write_text(json.dumps(spec))
    return path


def digests(out):
    out = pathlib.Path(out)
    return {str(f.relative_to(out)): hashlib.sha256(f.read_bytes()).hexdigest()
            for f in sorted(out.glob("item-*/*")) if f.name != "timing.json"}


def test_items_are_the_commands_bytes(tmp_path, cli):
    path = spec_files(tmp_path)
    cli("batch", path, "-o", tmp_path / "ref", "--quiet", "--threads", "1")
    spec = ringlet.BatchSpec(str(path))
    assert (spec.count, spec.views, spec.seed) == (4, 2, 2026)
    out = tmp_path / "py"
    out.mkdir()
    results = [ringlet.run_batch_item(spec, str(out), k, threads=2) for k in (3, 0, 2, 1)]
    assert [r["status"] for r in results] == ["done"] * 4
    assert digests(out) == digests(tmp_path / "ref")
    assert len(digests(out)) == 4 * 14  # hairstyle, 3 strand files, metadata, done, 2 x 4 images
    # The manifest lines are the command's.
    assert ({r["manifest_line"] for r in results} ==
            set((tmp_path / "ref" / "manifest-all.jsonl").read_text().splitlines()))
    assert set(results[0]["timing"]) == {"groom_seconds", "style_seconds", "render_seconds",
                                        "total_seconds"}
    # Done items are not made again: skipped, with the recorded status and the same line.
    again = ringlet.run_batch_item(spec, str(out), 3)
    assert again["status"] == "skipped" and again["recorded_status"] == "done"
    assert again["manifest_line"] == results[0]["manifest_line"] and again["timing"] is None
    # run_items: the range, in this process.
    out2 = tmp_path / "range"
    got = ringlet.batch.run_items(path, out2, 1, 3, threads=1)
    assert [r["item"] for r in got] == [1, 2]
    assert digests(out2) == {k: v for k, v in digests(out).items()
                             if k.startswith(("item-000000001", "item-000000002"))}


def test_resolve_is_the_plan(tmp_path, cli):
    path = spec_files(tmp_path)
    plan = [json.loads(l) for l in cli("batch", path, "--plan").stdout.splitlines()]
    spec = ringlet.BatchSpec(str(path))
    for k, line in enumerate(plan):
        item = ringlet.resolve_batch_item(spec, k)
        assert item["name"] == ringlet.batch_item_name(k) == line["name"]
        assert dict(item["parameters"], item=k, name=item["name"]) == line
        assert item["hairstyle"]["masters"]["count"] == line["values"]["masters.count"]


def test_errors(tmp_path, cli):
    path = spec_files(tmp_path)
    spec = ringlet.BatchSpec(str(path))
    with pytest.raises(ringlet.Error,
                       match=r"index: expected an item of the spec, in \[0, 4\), got 4"):
        ringlet.run_batch_item(spec, str(tmp_path), 4)
    with pytest.raises(ringlet.Error, match=r"threads: expected an integer in \[0, 1024\]"):
        ringlet.run_batch_item(spec, str(tmp_path), 0, threads=-1)
    bad = json.loads(path.read_text())
    bad["parameters"]["hair.curl_radious"] = {"uniform": [0.01, 0.02]}
    (tmp_path / "bad.json").write_text(json.dumps(bad))
    with pytest.raises(ringlet.Error) as raised:
        ringlet.BatchSpec(str(tmp_path / "bad.json"))
    assert str(raised.value) == cli_error(cli("batch", tmp_path / "bad.json", "--plan",
                                              check=False))
    with pytest.raises(ringlet.Error, match="line: expected one line"):
        ringlet.append_manifest_line(str(tmp_path / "m.jsonl"), "a\nb")


def test_half_written_items_are_never_trusted(tmp_path, cli):
    """A worker killed while writing an item leaves its temporary folder: the item is made
    again (the same bytes), and the engine removes the temporaries of dead workers only."""
    path = spec_files(tmp_path)
    cli("batch", path, "-o", tmp_path / "ref", "--quiet", "--items", "1:2")
    spec = ringlet.BatchSpec(str(path))
    out = tmp_path / "out"
    dead = out / ".item-000000001.tmp.otherhost.4242"
    dead.mkdir(parents=True)
    (dead / "hairstyle.json").write_text("{\"half\":")  # cut short by the kill
    (dead / "done").write_text("")
    alive = out / ".item-000000002.tmp.otherhost.4343"
    alive.mkdir()
    assert not ringlet.batch_item_done(str(out), "item-000000001")
    result = ringlet.run_batch_item(spec, str(out), 1)
    assert result["status"] == "done"
    assert digests(out) == digests(tmp_path / "ref")
    removed = ringlet.batch._remove_temporaries(str(out), [("otherhost", 4242)])
    assert removed == [dead.name] and not dead.exists() and alive.exists()
