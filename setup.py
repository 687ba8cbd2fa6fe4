# catkin_python_setup(): installs src/rigid_body_sim (the testing kit) beside the generated messages.
from setuptools import setup
from catkin_pkg.python_setup import generate_distutils_setup

setup(**generate_distutils_setup(packages=["rigid_body_sim"], package_dir={"": "src"}))
