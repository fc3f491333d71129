"""fecontact: finite element impact dynamics with exact unilateral contact."""

__version__ = "0.1.0"
