"""The report line of the checking scripts in this folder
(check_economy.py, check_output_times.py): check() prints ok or FAIL with
the message and counts the failures; finish() prints the count and exits 1
if any failed."""
import sys

failures = 0


def check(condition, message):
    global failures
    print(("ok   " if condition else "FAIL ") + message)
    failures += 0 if condition else 1


def finish():
    print(f"{failures} failures")
    sys.exit(1 if failures else 0)
