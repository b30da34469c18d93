"""Results bundles: the compact, committed record of a finished run, and what is done with one.

- :mod:`.make`: a bundle made from a results folder (the rule ``bundle``), its manifest and README;
- :mod:`.check`: a bundle checked against its manifest, one model's results read out of it;
- :mod:`.render`: a committed bundle re-rendered with the current code (``morphlearn render``);
- :mod:`.resimulate`: a bundle's designs re-simulated and compared bit for bit;
- :mod:`.verify`: stored cells re-evaluated with the scipy reference (``morphlearn verify``);
- :mod:`.scenario`: the scenario set's bundle.

Nothing is imported here: import the submodules.
"""
