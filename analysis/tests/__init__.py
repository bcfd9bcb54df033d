"""Tests of the analysis package: `/usr/bin/python3 -m unittest discover -s analysis/tests -t .`"""
