"""The reproduction table: every number the paper states about the two models, beside ours.

One row per quantity (``claims.QUANTITIES`` lists them; a test checks they are all present), with
the paper's value, ours, the config/resolution that produced ours and a note. Counts of
controllers scale with the weight grid (the paper used 121 x 121), so at a reduced resolution
compare the fractions (M_L) rather than the counts. A quantity this run cannot give (model
disabled, design not simulated) is reported as "not in this run", never dropped.

Modules, by job (imports point down this list; nothing is imported here, so the reproduction
rule depends only on the modules it runs):

- :mod:`.build`: the rule's work (load results, build the table and the persistence counts);
- :mod:`.writers`: CSV, Markdown, HTML; :mod:`.record`: the sealed custody record;
- :mod:`.table`: the paper's claims' rows, then each registered stage's;
- :mod:`.stage_registry`: the stages beyond the paper's claims (``stages/<name>.py`` + one line);
- :mod:`.claim_values`: ours for the paper's claims; :mod:`.selection`: which physics results a
  run holds; :mod:`.text`: counts and configuration notes; :mod:`.inputs`: what a table reads;
- :mod:`.claims`: the paper's claims and the paper's column of rows beyond it (data).
"""
