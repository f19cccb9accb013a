"""Writers for benchmark results: Markdown (paper layout), CSV and JSON."""

from .tables import markdown_table, result_to_dict, write_csv, write_json, write_markdown

__all__ = ["markdown_table", "result_to_dict", "write_csv", "write_json", "write_markdown"]
