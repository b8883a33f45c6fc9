"""Runs a GUI test command and checks its messages: every warning, error or
critical line must be one of the expected ones, and each expected message
must appear exactly once (for a test whose path has one warning on purpose).
The command's output is passed through, so ctest's PASS_REGULAR_EXPRESSION
still applies.

    python3 expect_messages.py --once REGEX [--once REGEX ...] -- COMMAND ARGS..."""
import re
import subprocess
import sys

args = sys.argv[1:]
split = args.index("--")
expected = [re.compile(args[i + 1]) for i in range(0, split, 2) if args[i] == "--once"]
result = subprocess.run(args[split + 1:], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                        text=True, errors="replace")
sys.stdout.write(result.stdout)
messages = [line for line in result.stdout.splitlines()
            if "WARN|" in line or "ERR|" in line or "critical:" in line]
seen = [0] * len(expected)
unexpected = []
for line in messages:
    matches = [k for k, pattern in enumerate(expected) if pattern.search(line)]
    if not matches:
        unexpected.append(line)
    for k in matches:
        seen[k] += 1
failed = False
for line in unexpected:
    print("unexpected message: " + line)
    failed = True
for pattern, count in zip(expected, seen):
    if count != 1:
        print("expected message %r seen %d times, not once" % (pattern.pattern, count))
        failed = True
sys.exit(1 if failed or result.returncode != 0 else 0)
