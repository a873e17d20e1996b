"""Install the robopuppet Python library (src/robopuppet) through catkin."""
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

PACKAGES = ['robopuppet', 'robopuppet.arm', 'robopuppet.baxter_sim', 'robopuppet.calibration',
            'robopuppet.config', 'robopuppet.episodes', 'robopuppet.ghost', 'robopuppet.gui',
            'robopuppet.protocol', 'robopuppet.puppet_sim']

setup(**generate_distutils_setup(packages=PACKAGES, package_dir={'': 'src'}))
