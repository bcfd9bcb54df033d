#!/usr/bin/env python3
"""`clothbench check --junit/--json`: the JUnit report has the structure CI systems read.

Usage: junit_report.py CLOTHBENCH SCENARIO WORKDIR

Runs a check whose gates fail (the chain's damping halved), then checks that the JUnit XML
has one test case per gate of the printed table and the JSON table, failure and skipped
counts equal to the table's, every attribute JUnit consumers read (tests, failures, errors,
skipped, time on the suites; name, classname, time on the cases; message on a failure naming
baseline, now and allowed); that an unwritable report path is refused at once (exit 2, no run)
and that a check that errors leaves an earlier report as it was.
"""
import json
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def run(args):
    return subprocess.run(args, capture_output=True, text=True)


def check_suite(suite, cases):
    for attribute in ("name", "tests", "failures", "errors", "skipped", "time"):
        if attribute not in suite.attrib:
            fail("testsuite without " + attribute)
    if int(suite.get("tests")) != len(cases):
        fail("suite tests=%s but %d test cases" % (suite.get("tests"), len(cases)))
    failures = sum(1 for c in cases if c.find("failure") is not None)
    skipped = sum(1 for c in cases if c.find("skipped") is not None)
    if int(suite.get("failures")) != failures or int(suite.get("skipped")) != skipped:
        fail("suite counts differ from its test cases")
    if float(suite.get("time")) <= 0:
        fail("suite time %s is not the check's wall time" % suite.get("time"))
    for case in cases:
        for attribute in ("name", "classname", "time"):
            if attribute not in case.attrib:
                fail("testcase without " + attribute)
        f = case.find("failure")
        if f is not None and not re.match(r"baseline .*, now .*, difference .*, allowed ",
                                          f.get("message", "")):
            fail("failure message without baseline, now, allowed: " + f.get("message", ""))


def table_counts(stdout):
    """(gates, failed, not gated) of the summary line, and the number of table rows."""
    m = re.search(r"^(\d+) gates passed, (\d+) failed, (\d+) not gated$", stdout, re.M)
    if not m:
        fail("no summary line in check's output")
    passed, failed, ungated = map(int, m.groups())
    return passed + failed + ungated, failed, ungated, len(stdout.splitlines()) - 2


def main():
    clothbench, scenario, work = sys.argv[1:4]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    xml_path, json_path = os.path.join(work, "gates.xml"), os.path.join(work, "gates.json")
    r = run([clothbench, "check", scenario, "-q", "--set", "cloth.damping=10",
             "--junit", xml_path, "--json", json_path])
    if r.returncode != 1:
        fail("expected exit status 1 (gates failed), got %d: %s" % (r.returncode, r.stderr))
    total, failed, ungated, table_rows = table_counts(r.stdout)
    if total != table_rows or failed == 0:
        fail("the printed table has %d rows for %d gates" % (table_rows, total))

    root = ET.parse(xml_path).getroot()
    if root.tag != "testsuites":
        fail("root element is %s, not testsuites" % root.tag)
    suites = root.findall("testsuite")
    cases = [c for s in suites for c in s.findall("testcase")]
    for s in suites:
        check_suite(s, s.findall("testcase"))
    xml_failures = sum(1 for c in cases if c.find("failure") is not None)
    xml_skipped = sum(1 for c in cases if c.find("skipped") is not None)
    if (len(cases), xml_failures, xml_skipped) != (total, failed, ungated):
        fail("JUnit has %d cases, %d failures, %d skipped; the table %d, %d, %d"
             % (len(cases), xml_failures, xml_skipped, total, failed, ungated))
    if (int(root.get("tests")), int(root.get("failures")), int(root.get("errors"))) != (
            total, failed, 0):
        fail("testsuites totals differ from the table")

    table = json.load(open(json_path))
    gates = table["gates"]
    if (len(gates), table["failed"], table["not_gated"]) != (total, failed, ungated):
        fail("JSON counts differ from the table")
    names = [c.get("classname").split(".")[-1] + " " + c.get("name") for c in cases]
    if names != ["%s %s %s" % (g["scenario"], g["engine"], g["quantity"]) for g in gates]:
        fail("JSON and JUnit name different gates")
    if [c.find("failure") is not None for c in cases] != [g["gated"] and not g["pass"] for g in gates]:
        fail("JSON and JUnit fail different gates")

    # an unwritable path is refused before any run
    r = run([clothbench, "check", scenario, "-q", "--junit", os.path.join(work, "no", "x.xml")])
    if r.returncode != 2 or r.stdout or "no" not in r.stderr:
        fail("unwritable --junit: exit %d, stdout %r, stderr %r" % (r.returncode, r.stdout, r.stderr))
    # a check that errors leaves the earlier report as it was, and no temporary file
    before = open(xml_path).read()
    r = run([clothbench, "check", scenario, "-q", "--set", "no.such.key=1", "--junit", xml_path])
    if r.returncode != 2 or open(xml_path).read() != before:
        fail("a failed check changed the earlier report (exit %d)" % r.returncode)
    if sorted(os.listdir(work)) != ["gates.json", "gates.xml"]:
        fail("files left behind: %s" % os.listdir(work))
    print("JUnit report: %d test cases in %d suites, %d failures, %d skipped, as in the table"
          % (len(cases), len(suites), failed, ungated))


if __name__ == "__main__":
    main()
