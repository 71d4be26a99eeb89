"""The results page (`uavdamp.results.page.Page`) as Markdown and as a standalone, styled HTML page.

`to_markdown(page)` links the figures relative to the page; `to_html(page, images)` embeds them (`images`: role
path -> PNG bytes, as data URIs) so the one file is the whole page, in a browser or in Snakemake's report.
"""

from __future__ import annotations

import base64
import html
import re

from uavdamp.results.page import Page, Table

CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", Helvetica, Arial, sans-serif; max-width: 1100px;
       margin: 2em auto; padding: 0 1em; color: #1f2328; line-height: 1.45; }
h1 { font-size: 1.7em; margin-bottom: 0.2em; } h2 { font-size: 1.25em; margin-top: 1.8em;
     border-bottom: 1px solid #d0d7de; padding-bottom: 0.2em; }
table { border-collapse: collapse; margin: 0.6em 0; font-size: 0.9em; }
th, td { padding: 0.25em 0.7em; text-align: right; border-bottom: 1px solid #e5e7eb; }
th { background: #f3f4f6; border-bottom: 2px solid #9ca3af; }
td.label, th.label { text-align: left; }
tbody tr:nth-child(even) { background: #fafafa; }
.note, .provenance, figcaption { color: #57606a; font-size: 0.9em; }
figure { margin: 1em 0; } figure img { max-width: 100%; border: 1px solid #e5e7eb; }
dt { font-weight: 600; } dd { margin: 0 0 0.4em 1.5em; }
code { font-size: 0.9em; }
"""


def _html_inline(text: str) -> str:
    """Escaped text with the Markdown bold of the findings as <strong>."""
    return re.sub(r"\*\*(.+?)\*\*", r"<strong>\1</strong>", html.escape(text))


def _md_table(table: Table) -> list[str]:
    frame = table.frame
    head = "| " + " | ".join(frame.columns) + " |"
    n = table.labels
    rule = "|" + "|".join(":---" if i < n else "---:" for i in range(len(frame.columns))) + "|"
    rows = ["| " + " | ".join(str(v) for v in row) + " |" for row in frame.itertuples(index=False)]
    return [head, rule, *rows]


def to_markdown(page: Page) -> str:
    """The page as Markdown: provenance, findings, descriptions, figures (relative links), tables."""
    lines = ["# Results of the run", ""]
    lines += [f"- {key}: `{value}`" for key, value in page.provenance.items()]
    lines += ["", "## Findings", "", *(f"- {s}" for s in page.findings), ""]
    for title, entries in page.descriptions:
        lines += [f"## {title}", "", *(f"- **{k}**: {v}" for k, v in entries.items()), ""]
    if page.figures:
        lines += ["## Figures", ""]
        for fig in page.figures:
            lines += [f"![{fig.title}]({fig.path})", "", f"*{fig.title}.* {fig.caption}", ""]
    for table in page.tables:
        lines += [f"## {table.title}", ""]
        lines += [table.note, ""] if table.note else []
        lines += [*_md_table(table), ""]
    return "\n".join(lines)


def landing_rst(intro: str, page: Page, html_name: str) -> str:
    """The report's first page: `intro` (reStructuredText), then the findings and a link to the results page
    (`html_name`, as Snakemake's report names its entries)."""
    findings = [f"- {s}" for s in page.findings]
    link = f"The whole results page (tables, cases, strategies, figures): {html_name}_."
    return "\n".join([intro.rstrip(), "", "Findings", "--------", "", *findings, "", link, ""])


def _html_table(table: Table) -> list[str]:
    n = table.labels

    def cls(i):
        return ' class="label"' if i < n else ""

    head = "".join(f"<th{cls(i)}>{html.escape(str(c))}</th>" for i, c in enumerate(table.frame.columns))
    rows = [
        "<tr>" + "".join(f"<td{cls(i)}>{html.escape(str(v))}</td>" for i, v in enumerate(row)) + "</tr>"
        for row in table.frame.itertuples(index=False)
    ]
    return ["<table>", f"<thead><tr>{head}</tr></thead>", "<tbody>", *rows, "</tbody>", "</table>"]


def to_html(page: Page, images: dict[str, bytes] | None = None) -> str:
    """The page as one standalone HTML document; `images` (a figure's path -> PNG bytes) embedded as data URIs,
    a figure without its bytes linked by its relative path."""
    images = images or {}
    body = ["<h1>Results of the run</h1>", '<ul class="provenance">']
    body += [f"<li>{html.escape(k)}: <code>{html.escape(v)}</code></li>" for k, v in page.provenance.items()]
    body += ["</ul>", "<h2>Findings</h2>", "<ul>", *(f"<li>{_html_inline(s)}</li>" for s in page.findings), "</ul>"]
    for title, entries in page.descriptions:
        body += [f"<h2>{html.escape(title)}</h2>", "<dl>"]
        body += [f"<dt>{html.escape(k)}</dt><dd>{html.escape(v)}</dd>" for k, v in entries.items()]
        body += ["</dl>"]
    if page.figures:
        body += ["<h2>Figures</h2>"]
        for fig in page.figures:
            data = images.get(fig.path)
            src = f"data:image/png;base64,{base64.b64encode(data).decode()}" if data else html.escape(fig.path)
            body += [
                "<figure>",
                f'<img src="{src}" alt="{html.escape(fig.title)}">',
                f"<figcaption><strong>{html.escape(fig.title)}.</strong> {html.escape(fig.caption)}</figcaption>",
                "</figure>",
            ]
    for table in page.tables:
        body += [f"<h2>{html.escape(table.title)}</h2>"]
        body += [f'<p class="note">{html.escape(table.note)}</p>'] if table.note else []
        body += _html_table(table)
    return "\n".join(
        [
            "<!doctype html>",
            '<html lang="en">',
            "<head>",
            '<meta charset="utf-8">',
            '<meta name="viewport" content="width=device-width, initial-scale=1">',
            "<title>uavdamp: results of the run</title>",
            f"<style>{CSS}</style>",
            "</head>",
            "<body>",
            *body,
            "</body>",
            "</html>",
            "",
        ]
    )
