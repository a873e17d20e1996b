"""The simulated participant's questionnaire answers: plausible, seeded (pure)."""
import numpy as np

from robopuppet import interface

TLX_MEAN = {'puppet': 30.0, 'marker': 45.0, 'gamepad': 50.0, 'spacemouse': 55.0,
            'keyboard': 65.0}   # how hard each device feels to the model operator, 0..100


def answers(device, seed):
    """Return (6 NASA-TLX ratings 0..100 in steps of 5, 10 SUS answers 1..5) for a device,
    plausible and seeded: a harder device rates higher workload and lower usability."""
    rng = np.random.default_rng([seed, interface.STUDY_DEVICES.index(device)])
    workload = TLX_MEAN[device]
    tlx = [float(min(100, max(0, 5 * round((workload + 12.0 * rng.standard_normal()) / 5))))
           for _ in range(6)]
    ease = 1.0 - workload / 100.0
    sus = []
    for item in range(10):
        agree = 1.0 + 4.0 * (ease if item % 2 == 0 else 1.0 - ease)
        sus.append(int(min(5, max(1, round(agree + 0.6 * rng.standard_normal())))))
    return tlx, sus
