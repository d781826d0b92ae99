"""Prompt length in tokens, per environment and prompt version, with a real model's tokenizer.

    python benchmarks/prompt_tokens.py --model-path qwen2.5-coder-1.5b-instruct-q4_k_m.gguf

Counts the tokens of the system and user messages of ``vlb synthesize``'s first request (the
paper's first prompt as the task; the shipped library), as the model's chat template lays them
out. Needs the ``llm`` extra (the tokenizer is read from the GGUF file; no weights are loaded).
"""

from __future__ import annotations

import argparse
import tempfile

import gymnasium as gym
from llama_cpp import Llama
from llama_cpp.llama_chat_format import Jinja2ChatFormatter

import vlb_gym  # noqa: F401  (registers the environments)
from vlb_gym.abstractor.paper import PROMPTS
from vlb_gym.abstractor.prompt import PROMPT_VERSIONS, PromptContext, build_messages
from vlb_gym.core.library import BehaviorLibrary

ENVS = ("VLB-GridExplore-v0", "VLB-Scoop-v0")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--model-path", required=True, metavar="FILE.gguf")
    args = parser.parse_args()
    model = Llama(model_path=args.model_path, vocab_only=True, verbose=False)
    formatter = Jinja2ChatFormatter(model.metadata["tokenizer.chat_template"],
                                    eos_token="", bos_token="")
    print(f"tokenizer: {model.metadata.get('general.name', args.model_path)}\n")
    print("| environment | " + " | ".join(f"{v} tokens" for v in PROMPT_VERSIONS) + " | ratio |")
    print("|---|" + "---:|" * (len(PROMPT_VERSIONS) + 1))
    with tempfile.TemporaryDirectory() as empty:
        library = BehaviorLibrary(empty)
        for env_id in ENVS:
            context = PromptContext.build(gym.make(env_id), library)
            counts = []
            for version in PROMPT_VERSIONS:
                messages = build_messages(PROMPTS["behavior1"], context, version=version)
                text = formatter(messages=messages).prompt
                counts.append(len(model.tokenize(text.encode(), add_bos=False, special=True)))
            print(f"| {env_id} | " + " | ".join(f"{c:,}" for c in counts)
                  + f" | {counts[-1] / counts[0]:.2f} |")


if __name__ == "__main__":
    main()
