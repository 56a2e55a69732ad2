"""ringlet.render against `ringlet render`: the same hairstyle and settings give the PNG's
8-bit codes exactly; the linear image's shape, dtype and encoding."""
import matplotlib.image
import numpy as np
import pytest

import ringlet
from conftest import cli_error


def test_render_matches_the_commands_png(cli, tmp_path, small_style):
    path, _ = small_style
    png = tmp_path / "r.png"
    cli("render", path, "-o", png, "--width", 40, "--height", 30, "--spp", 2, "--quiet")
    reference = np.round(matplotlib.image.imread(str(png)) * 255).astype(np.uint8)[:, :, :3]
    groom = ringlet.groom(str(path))
    codes = ringlet.render(groom, width=40, height=30, samples_per_pixel=2, srgb=True)
    assert codes.shape == (30, 40, 3) and codes.dtype == np.uint8
    assert np.array_equal(codes, reference)
    linear, stats = ringlet.render(groom, width=40, height=30, samples_per_pixel=2,
                                   threads=1, return_stats=True)
    assert linear.shape == (30, 40, 3) and linear.dtype == np.float32
    assert not linear.flags.owndata and linear.base is not None  # the renderer's own buffer
    assert np.array_equal(ringlet.encode_srgb8(linear), reference)  # exposure 1 by default
    assert stats.camera_rays == 30 * 40 * 2 and stats.nan_samples == 0
    # Anti-vacuity: hair and body are in the picture (not a flat background).
    assert len(np.unique(reference.reshape(-1, 3), axis=0)) > 50


def test_render_errors(tmp_path):
    with pytest.raises(ringlet.Error) as info:
        ringlet.render()
    assert "nothing to render" in str(info.value)
    curves = ringlet.HairCurves([[0, 0, 0], [0, 0, -0.1]], [2], [1e-4, 1e-4])
    with pytest.raises(ringlet.Error) as info:
        ringlet.render(curves, settings={"width": -3})
    assert str(info.value).startswith("render.width")
