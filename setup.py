"""The package list that pyproject.toml cannot state: the ``cases/`` folder of the source tree
ships in the wheel as the package data ``fecontact.cases`` (the same files, not a copy kept in
the tree), so that an installed fecontact finds its bundled cases."""

from setuptools import find_packages, setup

setup(
    packages=[*find_packages(include=["fecontact", "fecontact.*"]), "fecontact.cases"],
    package_dir={"fecontact.cases": "cases"},
)
