"""What the repository checkers share (tests/tags/check_tags.py, tests/layering/check_includes.py):
the root they check and their --self-test harness.

A checker's self-test writes a clean synthetic tree and one tree per planted violation into a
temporary directory, runs the checker's own check on each and fails unless the clean tree passes and
every violating tree gives exactly one problem, at the planted file, with the expected text. So the
check itself can fail (ctest layering_checker_self_test, test_tags_checker_self_test).
"""
import os
import tempfile


def repo_root(argv, script):
    """The tree to check: argv[1], else the repository two folders above the checker `script`."""
    return os.path.abspath(argv[1] if len(argv) > 1 else os.path.join(os.path.dirname(script), "..", ".."))


def write(root, rel, text):
    """Writes text to root/rel, creating its folders."""
    path = os.path.join(root, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(text)


def run_self_test(problems_of, clean, violating, clean_failure, at):
    """Runs the checker on synthetic trees; returns the exit code (0: every case behaves, 1 otherwise).

    problems_of(root): the checker's problem lines for the tree at root.
    clean: {relative path: text} of a tree the checker must pass.
    violating: {what: (relative path, text, expected)}: the clean tree with that one file written (added
        or replaced) must give exactly one problem that starts with at(path) and contains expected.
    clean_failure(root): why the clean tree at root fails the checker, or None when it passes.
    """
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        root = os.path.join(tmp, "clean")
        for rel, text in clean.items():
            write(root, rel, text)
        why = clean_failure(root)
        if why:
            print(f"self-test FAILED: {why}")
            failures += 1
        for i, (what, (rel, text, expected)) in enumerate(violating.items()):
            root = os.path.join(tmp, f"bad{i}")
            for r, t in clean.items():
                write(root, r, t)
            write(root, rel, text)
            problems = problems_of(root)
            if len(problems) != 1 or not problems[0].startswith(at(rel)) or expected not in problems[0]:
                print(f"self-test FAILED: {what}: expected one problem at {at(rel)} containing '{expected}', got "
                      f"{problems}")
                failures += 1
            else:
                print(f"self-test ok: {what}: {problems[0]}")
    print("self-test: " + ("all cases behave" if failures == 0 else f"{failures} case(s) misbehave"))
    return 1 if failures else 0
