"""Install the robopuppet Python library (src/robopuppet) through catkin."""
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=['robopuppet', 'robopuppet.gui'], package_dir={'': 'src'}))
