"""read_image / write_image (MetaImage) and write_vti."""

import numpy as np
import pytest

import geovoronoi as gv


@pytest.mark.parametrize("dtype", [np.uint8, np.int16, np.uint32, np.int64, np.float32, np.float64])
@pytest.mark.parametrize("ext", [".mhd", ".mha"])
def test_round_trip_3d(tmp_path, dtype, ext):
    rng = np.random.default_rng(1)
    a = (rng.random((3, 4, 5)) * 100).astype(dtype)
    orient = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    gv.write_image(tmp_path / f"a{ext}", a, (3.0, 2.0, 0.5), (1.0, -2.0, 7.25), orient)
    b, spacing, origin, orientation = gv.read_image(tmp_path / f"a{ext}")
    assert b.dtype == dtype and b.shape == (3, 4, 5)
    assert np.array_equal(a, b)
    assert spacing == (3.0, 2.0, 0.5) and origin == (1.0, -2.0, 7.25)
    assert np.array_equal(orientation, orient)


def test_file_is_x_fastest_with_array_order_metadata(tmp_path):
    a = np.arange(6, dtype=np.float32).reshape(2, 3)  # [y, x]
    gv.write_image(tmp_path / "a.mhd", a, spacing=(2.0, 0.5))
    header = (tmp_path / "a.mhd").read_text()
    assert "DimSize = 3 2" in header and "ElementSpacing = 0.5 2" in header
    assert np.array_equal(np.fromfile(tmp_path / "a.raw", np.float32), a.ravel())
    b, spacing, origin, orientation = gv.read_image(tmp_path / "a.mhd")
    assert b.shape == (2, 3) and spacing == (2.0, 0.5) and origin == (0.0, 0.0)
    assert orientation.shape == (2, 2)


def test_channels_interleaved_and_planar(tmp_path):
    a = np.arange(2 * 3 * 4 * 2, dtype=np.uint32).reshape(2, 3, 4, 2)
    gv.write_image(tmp_path / "i.mha", a, channels=True)
    b, *_ = gv.read_image(tmp_path / "i.mha")
    assert np.array_equal(a, b)
    gv.write_image(tmp_path / "p.mhd", a, channels=True, planar=True)
    raw = np.fromfile(tmp_path / "p.raw", np.uint32)
    assert np.array_equal(raw, np.moveaxis(a, -1, 0).ravel())


@pytest.mark.skipif(not gv._ext._metaimage_has_zlib(), reason="built without zlib")
def test_compressed(tmp_path):
    a = np.zeros((8, 8, 8), np.float32)
    a[2] = 1
    gv.write_image(tmp_path / "c.mhd", a, compress=True)
    assert (tmp_path / "c.zraw").stat().st_size < a.nbytes
    assert np.array_equal(gv.read_image(tmp_path / "c.mhd")[0], a)


def test_read_errors(tmp_path):
    with pytest.raises(OSError, match="missing.mhd"):
        gv.read_image(tmp_path / "missing.mhd")
    (tmp_path / "bad.mhd").write_text("NDims = 3\nDimSize = 2 2\nElementType = MET_FLOAT\nElementDataFile = x.raw\n")
    with pytest.raises(OSError, match="bad.mhd"):
        gv.read_image(tmp_path / "bad.mhd")


def test_write_errors(tmp_path):
    with pytest.raises(TypeError, match="dtype"):
        gv.write_image(tmp_path / "a.mhd", np.ones((2, 2), complex))
    with pytest.raises(ValueError, match="orientation"):
        gv.write_image(tmp_path / "a.mhd", np.ones((2, 2)), orientation=np.eye(3))
    with pytest.raises(ValueError, match="spacing"):
        gv.write_image(tmp_path / "a.mhd", np.ones((2, 2)), spacing=(1.0, -1.0))
    with pytest.raises(OSError):
        gv.write_image(tmp_path / "no" / "such" / "a.mhd", np.ones((2, 2)))


def test_write_vti(tmp_path):
    f = np.ones((3, 4, 5), np.float32)
    d = gv.voronoi(f, [[0, 0, 0], [2, 3, 4]], backend="seq")
    gv.write_vti(tmp_path / "d.vti", {"label": d.label, "distance": d.distance, "vec": np.zeros((3, 4, 5, 3))},
                 spacing=(2.0, 1.0, 0.5))
    text = (tmp_path / "d.vti").read_bytes()
    assert b'WholeExtent="0 4 0 3 0 2"' in text and b'Spacing="0.5 1 2"' in text
    assert b'Name="label"' in text and b'type="Int32"' in text and b'NumberOfComponents="3"' in text
    with pytest.raises(ValueError, match="shape"):
        gv.write_vti(tmp_path / "e.vti", {"a": f, "b": np.ones((3, 4))})
    with pytest.raises(ValueError, match="at least one"):
        gv.write_vti(tmp_path / "e.vti", {})


def test_orientation_is_the_direction_matrix_itk_order(tmp_path):
    # in x, y, z order: index x runs along world +y, index y along world -x
    d_xyz = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    orient = d_xyz[::-1, ::-1]  # array-axis order (z, y, x)
    gv.write_image(tmp_path / "r.mha", np.zeros((2, 3, 4), np.uint8), orientation=orient)
    header = (tmp_path / "r.mha").read_bytes().split(b"ElementDataFile")[0].decode()
    assert "TransformMatrix = 0 1 0 -1 0 0 0 0 1\n" in header  # ITK lists D's columns
    assert np.array_equal(gv.read_image(tmp_path / "r.mha")[3], orient)
    with pytest.raises(ValueError, match="singular"):
        gv.write_image(tmp_path / "s.mha", np.zeros((2, 2)), orientation=np.zeros((2, 2)))
