"""The rows of each stage beyond the paper's own claims, one module per stage, each with
``rows(inputs) -> list[dict]``; ``stage_registry.STAGES`` lists them in table order. Nothing is
imported here."""
