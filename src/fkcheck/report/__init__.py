"""Writers of check results: JSON (the contract), JUnit XML, and (later) HTML and Markdown.

Every writer writes atomically (:func:`fkcheck.report.atomic.write_text_atomic`):
an interrupted run never leaves a truncated file behind.
"""
