"""The table's files: CSV, Markdown and HTML."""

from __future__ import annotations

from pathlib import Path

import pandas as pd


def to_markdown(table: pd.DataFrame) -> str:
    """A GitHub Markdown table (no extra dependency), config column once below the table."""
    esc = lambda s: str(s).replace("|", "\\|")  # noqa: E731
    lines = ["| quantity | paper | ours | note |", "|---|---|---|---|"]
    lines += [f"| {esc(r.quantity)} | {esc(r.paper)} | {esc(r.ours)} | {esc(r.note)} |" for r in table.itertuples()]
    configs = dict.fromkeys(table.config)
    return "\n".join(["# Reproduction table", "", *lines, "", "Configs:", "", *(f"- {c}" for c in configs), ""])


def write(table: pd.DataFrame, csv: str | Path, md: str | Path, html: str | Path) -> None:
    table.to_csv(csv, index=False)
    Path(md).write_text(to_markdown(table))
    Path(html).write_text(table.drop(columns=["key"]).to_html(index=False, border=0) + "\n")
