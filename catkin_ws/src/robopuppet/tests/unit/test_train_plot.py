"""train_assist's plot: unfamiliar spans and a PNG written."""
import numpy as np

import assist_synthetic
from robopuppet.assist import learners, train_plot


def test_unfamiliar_runs_become_spans():
    t = np.arange(10) * 0.1
    familiar = np.array([1, 0, 0, 1, 1, 0, 1, 1, 0, 0], bool)
    assert np.allclose(train_plot.unfamiliar_spans(t, familiar),
                       [(0.1, 0.3), (0.5, 0.6), (0.8, 1.0)])
    assert train_plot.unfamiliar_spans(t, np.ones(10, bool)) == []


def test_the_plot_is_a_png(tmp_path):
    demos = [assist_synthetic.demo(seed) for seed in range(3)]
    predictor = learners.train(demos, 'lwr', 'right', 'left')
    path = tmp_path / 'plot.png'
    shown, _ = assist_synthetic.unfamiliar(9)
    train_plot.write_plot(str(path), predictor, shown, 'title')
    assert path.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n' and path.stat().st_size > 20000
