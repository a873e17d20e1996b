"""Unit tests of png_plot: a figure written as a PNG and closed, also when writing fails."""
import pytest

from robopuppet import png_plot


def test_a_figure_is_written_as_png_and_closed(tmp_path):
    plt = png_plot.pyplot()
    figure, axis = plt.subplots(figsize=(2, 1))
    axis.plot([0, 1], [1, 0])
    path = tmp_path / 'plot.png'
    png_plot.write_png(str(path), figure)
    assert path.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'
    assert figure.number not in plt.get_fignums()


def test_a_figure_that_cannot_be_written_is_closed_too(tmp_path):
    plt = png_plot.pyplot()
    figure, _ = plt.subplots(figsize=(2, 1))
    with pytest.raises(OSError):
        png_plot.write_png(str(tmp_path / 'no such folder' / 'plot.png'), figure)
    assert figure.number not in plt.get_fignums()
