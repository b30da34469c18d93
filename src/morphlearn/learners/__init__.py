"""Real learners on the theory model: do the paper's metrics predict learning? (issue 15)

``objective`` (the per-environment loss, the batched evaluator), ``algorithms`` (random search,
(1+1)-ES, CMA-ES as ask/tell learners), ``protocols`` (joint and sequential runs as generators that
a driver batches across runs), ``stats`` (per-design summaries, Spearman with bootstrap intervals).
"""
