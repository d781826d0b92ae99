"""The paper's two natural-language requests (Sec. V-A) and replies an LLM would give to them,
used offline (scripted backend) by the examples, the tests and the comparison benchmark."""

import json
from pathlib import Path

PAPER = Path(__file__).resolve().parent
PROMPTS: dict[str, str] = json.loads((PAPER / "prompts.json").read_text())
