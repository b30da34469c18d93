"""morphlearn: how sensor placement shapes the learnability of a Braitenberg controller."""

__version__ = "0.1.0"
