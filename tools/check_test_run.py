#!/usr/bin/env python3
"""Checks that a ctest run ran what the build defines, and prints the stage's summary line.

Usage: check_test_run.py BUILD_DIR JUNIT_XML STAGE SECONDS [--strict] [--require-label L]...
                         [--counts FILE] [-- CTEST_SELECTION_ARGS...]

1. Every test case each Catch executable lists (--list-test-names-only) has exactly one ctest
   entry named "<executable>: <test case>", and ctest has no entry of that executable that names
   no test case (a name that discovery split, say at a ';').
2. Of the entries the selection chose (the ctest arguments after --), each ran (the JUnit file of
   `ctest --output-junit`): none missing from the run; skipped ones are listed with the reason
   they printed. With --strict (tools/test.sh under CI=true or PPCR_STRICT=1) a skip fails, and
   each --require-label must have at least one test that ran.
Prints "== STAGE: N tests run (P passed, F failed), S skipped, T s" and the skips' reasons;
--counts writes "N P F S" to FILE. Exits 1 when a check fails (after saying which), else 0.
"""
import collections
import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

SKIP_MARKER = "PPCR-TEST-SKIPPED:"


def ctest_tests(build, selection):
    out = subprocess.run(["ctest", "--test-dir", build, "--show-only=json-v1", *selection],
                         check=True, capture_output=True, text=True).stdout
    tests = []
    for t in json.loads(out)["tests"]:
        labels = []
        for p in t.get("properties", []):
            if p["name"] == "LABELS":
                labels = p["value"]
        tests.append({"name": t["name"], "command": t.get("command", []), "labels": labels})
    return tests


def catch_executables(tests):
    """{executable path: [ctest names]} for the entries ppcr_add_test made ("<exe>: <case>")."""
    groups = collections.defaultdict(list)
    for t in tests:
        if t["command"]:
            exe = t["command"][0]
            if t["name"].startswith(os.path.basename(exe) + ": "):
                groups[exe].append(t["name"])
    return groups


def check_discovery(tests, groups):
    errors = [f"'{t['name']}': an executable was not built, or its test cases were not listed"
              for t in tests if t["name"].endswith("_NOT_BUILT")]
    for exe, names in sorted(groups.items()):
        prefix = os.path.basename(exe) + ": "
        listed = subprocess.run([exe, "--list-test-names-only"], capture_output=True, text=True,
                                cwd=os.path.dirname(exe)).stdout
        cases = [line.rstrip("\r") for line in listed.splitlines() if line.strip()]
        in_ctest = collections.Counter(n[len(prefix):] for n in names)
        in_catch = collections.Counter(cases)
        if not cases:
            errors.append(f"{exe} lists no test case")
        for case in sorted(in_catch - in_ctest):
            errors.append(f"{prefix}'{case}' has no ctest entry of its own")
        for case in sorted(in_ctest - in_catch):
            errors.append(f"{prefix}ctest entry '{case}' names no test case of the executable")
        for case, n in sorted(in_ctest.items()):
            if n > 1:
                errors.append(f"{prefix}'{case}' has {n} ctest entries")
    return errors


def junit_results(path):
    """{test name: (status, reason)} with status 'passed', 'failed' or 'skipped'."""
    results = {}
    for case in ET.parse(path).getroot().iter("testcase"):
        name = case.get("name")
        out = case.findtext("system-out") or ""
        if case.find("failure") is not None or case.get("status") == "fail":
            results[name] = ("failed", "")
        elif case.find("skipped") is not None or case.get("status") in ("notrun", "disabled"):
            reason = next((line.split(SKIP_MARKER, 1)[1].strip()
                           for line in out.splitlines() if SKIP_MARKER in line), None)
            if reason is None:
                skipped = case.find("skipped")
                reason = skipped.get("message", "") if skipped is not None else "not run"
            results[name] = ("skipped", reason)
        else:
            results[name] = ("passed", "")
    return results


def main(argv):
    selection = []
    if "--" in argv:
        at = argv.index("--")
        argv, selection = argv[:at], argv[at + 1:]
    build, junit, stage, seconds = argv[:4]
    options = argv[4:]
    strict = "--strict" in options
    required = [options[i + 1] for i, o in enumerate(options) if o == "--require-label"]
    counts_file = next((options[i + 1] for i, o in enumerate(options) if o == "--counts"), None)

    all_tests = ctest_tests(build, [])
    errors = check_discovery(all_tests, catch_executables(all_tests))
    selected = ctest_tests(build, selection)
    results = junit_results(junit) if os.path.isfile(junit) else {}
    if not os.path.isfile(junit):
        errors.append(f"no JUnit file {junit}: ctest did not run")
    for t in selected:
        if t["name"] not in results:
            errors.append(f"'{t['name']}' was selected but did not run")
    ran = [results[t["name"]] for t in selected if t["name"] in results]
    passed = sum(1 for status, _ in ran if status == "passed")
    failed = sum(1 for status, _ in ran if status == "failed")
    skips = sorted((t["name"], results[t["name"]][1]) for t in selected
                   if results.get(t["name"], ("",))[0] == "skipped")
    if not selected:
        errors.append("the selection holds no test")
    if strict:
        for name, reason in skips:
            errors.append(f"'{name}' skipped ({reason}): under CI=true or PPCR_STRICT=1 every "
                          "test must run")
        for label in required:
            if not any(label in t["labels"] and results.get(t["name"], ("",))[0] == "passed"
                       for t in selected):
                errors.append(f"no test labelled '{label}' ran and passed")

    print(f"== {stage}: {passed + failed} tests run ({passed} passed, {failed} failed), "
          f"{len(skips)} skipped, {seconds} s")
    reasons = collections.Counter(reason for _, reason in skips)
    for reason, n in sorted(reasons.items()):
        print(f"   skipped {n}: {reason}")
    if counts_file:
        with open(counts_file, "w") as f:
            f.write(f"{passed + failed} {passed} {failed} {len(skips)}\n")
    for e in errors:
        print(f"check_test_run ({stage}): {e}", file=sys.stderr)
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
