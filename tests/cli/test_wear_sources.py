"""hipsim.cli.wear_sources by hand: a file's kind from its columns (simulate before stations before a rig log), its
header read from CSV, ``FILE[:TAG]`` split unless the file's own name holds the colon."""

from __future__ import annotations

import pytest

from hipsim.cli.wear_sources import header, kind_of, split_source
from hipsim.exceptions import HipsimError


def test_a_files_kind_from_its_columns_in_order():
    assert kind_of({"t_s", "alpha_des_deg", "alpha_1_deg", "tau_1_Nmm"}) == "simulate"  # simulate has torques too
    assert kind_of({"t_s", "alpha_1_deg", "tau_1_Nmm"}) == "stations"
    assert kind_of({"t_s", "tau_1_Nmm"}) == "rig log"
    assert kind_of({"t_s", "current_1_A"}) == "rig log"
    assert kind_of({"t_s", "alpha_deg", "beta_deg", "gamma_deg"}) == "trajectory"
    assert kind_of(set()) == "trajectory"


def test_a_header_from_a_csv_or_none(tmp_path):
    csv = tmp_path / "a.csv"
    csv.write_text("# a comment\nt_s; alpha_deg ;beta_deg\n0;1;2\n0.1;1;2\n")
    assert header(str(csv)) == {"t_s", "alpha_deg", "beta_deg"}  # cells stripped, ';' found
    mot = tmp_path / "b.mot"
    mot.write_text("t_s,alpha_deg\n")
    assert header(str(mot)) == set()  # an OpenSim file: its reader tells
    assert header(str(tmp_path / "missing.csv")) == set()  # its reader says why
    empty = tmp_path / "c.csv"
    empty.write_text("# nothing but a comment\n")
    assert header(str(empty)) == set()


def test_file_and_tag(tmp_path):
    assert split_source("run.csv") == ("run.csv", None)
    assert split_source("out.csv:1") == ("out.csv", "1")
    assert split_source("out.csv:2") == ("out.csv", "2")
    assert split_source("sim.csv:desired") == ("sim.csv", "desired")
    odd = tmp_path / "a:1.csv"
    odd.write_text("t_s\n")
    assert split_source(str(odd)) == (str(odd), None)  # the colon is the file's own
    with pytest.raises(HipsimError, match=r"^out\.csv:3: expected FILE, FILE:1, FILE:2 .* or FILE:desired"):
        split_source("out.csv:3")
