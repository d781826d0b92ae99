"""Reports people read: a finished campaign as report.json, report.md and one self-contained
report.html (the claim in words, the numbers, failures by cause with replay commands, the
behavior graph coloured by failed certificates, confidence against eps, per-episode charts,
frames and provenance).

Modules: :mod:`.content` decides what the report says, as blocks of :mod:`vlb_gym.core.document` (which the statistical methods also write their paragraphs in);
:mod:`.markdown` and :mod:`.html` render them; :mod:`.graph`, :mod:`.plots` and :mod:`.png` make
the pictures; :mod:`.attribution` counts failed certificates per node; :mod:`.writer` writes
the folder.
"""

from .writer import report_data, write_report_dir

__all__ = ["report_data", "write_report_dir"]
