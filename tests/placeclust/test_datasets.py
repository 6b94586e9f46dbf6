import cv2
import numpy as np
import pytest

from placeclust.datasets import DatasetError, ImageFolder, natural_key, write_image_folder


def _frames(n=4, seed=0):
    return np.random.default_rng(seed).integers(0, 255, (n, 24, 32, 3), np.uint8)


def test_a_written_folder_reads_back_frame_for_frame(tmp_path):
    frames = _frames()
    poses = np.arange(12, dtype=float).reshape(4, 3)
    write_image_folder(tmp_path, frames, ["a", "a", "b", ""], poses, "night")
    folder = ImageFolder(tmp_path)
    assert len(folder) == 4
    assert all(np.array_equal(f, g) for f, g in zip(folder, frames))  # png is lossless
    assert np.array_equal(folder[2], frames[2])
    assert folder.labels.tolist() == [0, 0, 1, -1] and folder.label_names == ["a", "b"]
    assert np.allclose(folder.poses, poses) and folder.conditions == ["night"] * 4


def test_images_are_read_when_asked_not_held(tmp_path):
    write_image_folder(tmp_path, _frames(2))
    folder = ImageFolder(tmp_path)
    cv2.imwrite(str(folder.files[1]), np.zeros((24, 32, 3), np.uint8))
    assert folder[1].max() == 0  # decoded from disk on access: a folder is never held whole


def test_frames_come_in_natural_order_and_labels_name_them_or_their_index(tmp_path):
    for name in ("img10.png", "img2.png", "img1.jpg"):
        cv2.imwrite(str(tmp_path / name), np.full((20, 20, 3), 9, np.uint8))
    (tmp_path / "labels.csv").write_text("frame,label\nimg10.png,c\n0,a\nimg2.png,b\n")
    folder = ImageFolder(tmp_path)
    assert [f.name for f in folder.files] == ["img1.jpg", "img2.png", "img10.png"]
    assert folder.label_names == ["a", "b", "c"] and folder.labels.tolist() == [0, 1, 2]
    assert sorted(["x10", "x9", "X1"], key=natural_key) == ["X1", "x9", "x10"]
    assert ImageFolder(tmp_path, labels=False).labels is None


@pytest.mark.parametrize("labels, message", [
    ("frame,place\n", "must have the columns frame,label"),
    ("frame,label\n000000.png,a\n", "no row for 1 of the 2 images"),
    ("frame,label\n000000.png,a\n000000.png,b\n000001.png,a\n", "labelled twice"),
    ("frame,label\n000000.png,a\nnope.png,b\n", "line 3: frame 'nope.png' is not an image"),
    ("frame,label,x,y,heading\n000000.png,a,1,2,x\n000001.png,a,1,2,3\n", "must be numbers"),
])
def test_a_labels_file_that_does_not_match_is_named(tmp_path, labels, message):
    write_image_folder(tmp_path, _frames(2))
    (tmp_path / "labels.csv").write_text(labels)
    with pytest.raises(DatasetError, match=message) as err:
        ImageFolder(tmp_path)
    assert "labels.csv" in str(err.value)


def test_missing_empty_and_unreadable_folders_are_named(tmp_path):
    with pytest.raises(DatasetError, match="does not exist"):
        ImageFolder(tmp_path / "nope")
    (tmp_path / "notes.txt").write_text("x")
    with pytest.raises(DatasetError, match="notes.txt is a file; give the folder"):
        ImageFolder(tmp_path / "notes.txt")  # not "does not exist": it does
    with pytest.raises(DatasetError, match="holds no image"):
        ImageFolder(tmp_path)
    (tmp_path / "000.png").write_text("not an image")
    with pytest.raises(DatasetError, match="000.png"):
        ImageFolder(tmp_path)


def test_an_image_damaged_past_its_header_fails_when_read(tmp_path):
    write_image_folder(tmp_path, _frames(2))
    path = ImageFolder(tmp_path).files[1]
    path.write_bytes(path.read_bytes()[:40])  # the png signature stays, the data is gone
    folder = ImageFolder(tmp_path)
    with pytest.raises(DatasetError, match="cannot read image"):
        list(folder)
