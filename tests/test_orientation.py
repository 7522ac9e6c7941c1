"""Files keep the drawing's orientation: y-up shapes are upright in SVG, y-down ones in OBJ/OFF."""

import numpy as np
import pytest

from browser import screenshot
from isotween import Sequence, Shape, io
from isotween.io._mesh import Y_DOWN_NOTE
from isotween.render import write_frame_png

UP = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 2.0]])  # y-up: apex on top


def png(shape, path):
    from PIL import Image

    write_frame_png(shape, path, size=120)
    with Image.open(path) as im:
        return np.asarray(im.convert("RGB"))


def same_picture(a, b):
    """Equal up to anti-aliasing rounding (mirrored geometry rasterises 1 level apart)."""
    return np.abs(a.astype(int) - b).max() <= 2


def ink_rows(rgb, threshold=160):
    """Widths of the drawn span of every row that has ink, top to bottom."""
    dark = rgb.min(axis=2) < threshold
    rows = np.flatnonzero(dark.any(axis=1))
    cols = [np.flatnonzero(dark[r]) for r in rows]
    return np.array([c[-1] - c[0] + 1 for c in cols])


def test_static_svg_of_a_y_up_shape_reads_back_as_the_same_drawing(tmp_path):
    shape = Shape.from_polygon(UP)
    io.save(shape, tmp_path / "t.svg")
    back = io.load(tmp_path / "t.svg")
    # written upright as (x, -y) and marked so: it reads back exactly as the y-up shape it was
    assert not back.y_down
    np.testing.assert_array_equal(back.vertices, UP)
    np.testing.assert_array_equal(back.edges, shape.edges)
    # drawn by isotween, both are the same picture (the file's default stroke paint set aside)
    plain = Shape(back.vertices, back.edges, paths=back.paths)
    assert same_picture(png(plain, tmp_path / "b.png"), png(shape, tmp_path / "a.png"))
    # the file holds the upright drawing: without the mark it reads as the y-down shape (x, -y)
    unmarked = tmp_path / "u.svg"
    unmarked.write_text((tmp_path / "t.svg").read_text().replace(' data-isotween-y="up"', ""))
    drawn = io.load(unmarked)
    assert drawn.y_down
    np.testing.assert_array_equal(drawn.vertices, UP * [1, -1])
    # a y-down shape is written as it is and reads back exactly
    io.save(drawn, tmp_path / "d.svg")
    np.testing.assert_array_equal(io.load(tmp_path / "d.svg").vertices, drawn.vertices)


@pytest.mark.parametrize("ext", [".obj", ".off"])
def test_y_down_shape_in_obj_and_off_keeps_its_look(tmp_path, ext):
    down = Shape.from_polygon(UP * [1, -1])
    down = Shape(down.vertices, down.edges, paths=down.paths, y_down=True)
    io.save(down, tmp_path / f"s{ext}")
    back = io.load(tmp_path / f"s{ext}")
    # written with y negated and a note saying so: it reads back exactly as the y-down shape it was
    assert back.y_down
    np.testing.assert_array_equal(back.vertices, down.vertices)
    assert same_picture(png(back, tmp_path / "b.png"), png(down, tmp_path / "a.png"))
    # the file holds the upright shape: a reader that ignores the note sees it y-up, drawn the same way
    plain = tmp_path / f"plain{ext}"
    plain.write_text((tmp_path / f"s{ext}").read_text().replace(Y_DOWN_NOTE, "#"))
    upright = io.load(plain)
    assert not upright.y_down
    np.testing.assert_array_equal(upright.vertices, UP)
    assert same_picture(png(upright, tmp_path / "c.png"), png(down, tmp_path / "a.png"))


def test_prepare_output_draws_like_the_svg_inputs(tmp_path):
    from click.testing import CliRunner

    from isotween.cli import main

    a = Shape(UP * [1, -1], Shape.from_polygon(UP).edges, paths=Shape.from_polygon(UP).paths, y_down=True)
    io.save(a, tmp_path / "a.svg")
    io.save(a.with_vertices(a.vertices * 1.5), tmp_path / "b.svg")
    result = CliRunner().invoke(main, ["prepare", str(tmp_path / "a.svg"), str(tmp_path / "b.svg"),
                                       "--resample", "12", "-o", str(tmp_path / "pair")])
    assert result.exit_code == 0, result.output
    src = io.load(sorted((tmp_path / "pair").glob("*.obj"))[0])
    widths = ink_rows(png(src, tmp_path / "s.png"))
    assert widths[:5].mean() < 0.3 * widths[-5:].mean()  # apex on top, base at the bottom


def test_browser_draws_a_y_up_triangle_pointing_up(tmp_path, browser):
    shape = Shape.from_polygon(UP)
    io.save(shape, tmp_path / "t.svg")
    seq = Sequence(np.stack([UP, UP + [3.0, 0.0]]), shape)
    files = io.write_frames(seq, tmp_path / "frames", format="svg")
    page = browser.new_page(viewport={"width": 520, "height": 520})
    try:
        for path in [tmp_path / "t.svg", *files]:
            page.goto(path.as_uri())
            widths = ink_rows(screenshot(page))
            assert len(widths) > 100, path
            assert widths[:10].mean() < 0.2 * widths[-10:].mean(), path  # narrow apex on top
    finally:
        page.close()
