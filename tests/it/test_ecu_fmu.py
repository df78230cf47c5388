"""hdlamp ecu --fmu (docs/ecu.md, "The ECU as an FMU"): the FMU's ZIP layout, its
modelDescription.xml (every input of ecu/io.h by name, an output per source: 190 for the HD84
pair, discrete Reals, the outputs listed in ModelStructure), the options it carries in
resources/ecu.json, and the same bytes from two exports of the same inputs. That the shared
object computes the in-process reference's bits is tests/unit/ecu/test_ecu_fmu.c."""
import filecmp
import json
import os
import xml.etree.ElementTree as ET
import zipfile

from proc import run

HDLAMP = os.environ["HDLAMP"]

VEHICLE = ["VEH_Speed", "VEH_YawRate", "VEH_SteeringAngle", "VEH_LightSwitch", "VEH_AdbEnable"]
OBJECT = ["CAMI_ObjId", "CAMI_ObjClass", "CAMB_HLeft", "CAMB_HRight", "CAMB_VBottom",
          "CAMB_VTop", "CAMI_Distance", "CAMI_Confidence"]
COM = ["COM_VehicleRxTime", "COM_ObjectsRxTime", "COM_VehicleE2EErrors", "COM_ObjectsE2EErrors"]


def export(path, *args):
    run(HDLAMP, "ecu", "--fmu", path, *args)
    return zipfile.ZipFile(path)


def test_model_description_names_every_input_and_output(tmp_path):
    z = export(tmp_path / "ecu.fmu", "--fault", "ignore-objects", "--margin-deg", "1")
    names = z.namelist()
    assert names[0] == "modelDescription.xml"
    assert "binaries/linux64/hdlamp_ecu.so" in names
    assert "resources/ecu.json" in names and "resources/hd84_inputs.dbc" in names
    assert all(i.compress_type == zipfile.ZIP_DEFLATED for i in z.infolist())
    md = ET.fromstring(z.read("modelDescription.xml"))
    assert md.get("fmiVersion") == "2.0"
    assert md.get("generationTool").startswith("hdlamp ")
    assert md.find("CoSimulation").get("modelIdentifier") == "hdlamp_ecu"
    assert md.find("DefaultExperiment").get("stepSize") == "0.02"
    svs = md.find("ModelVariables").findall("ScalarVariable")
    inputs = [v for v in svs if v.get("causality") == "input"]
    outputs = [v for v in svs if v.get("causality") == "output"]
    want = VEHICLE + ["CAMI_ObjCount"] + [f"{n}[{k}]" for n in OBJECT for k in range(8)] + COM
    assert [v.get("name") for v in inputs] == want
    assert len(outputs) == 190
    assert outputs[0].get("name") == "left.row1_led01"
    assert outputs[95].get("name") == "right.row1_led01"
    for i, v in enumerate(svs):
        assert v.get("valueReference") == str(i)
        assert v.get("variability") == "discrete"
        assert v.find("Real") is not None
    start = {v.get("name"): float(v.find("Real").get("start")) for v in inputs}
    assert start["COM_VehicleRxTime"] == -1 and start["VEH_Speed"] == 0
    unknowns = md.find("ModelStructure").find("Outputs").findall("Unknown")
    assert [int(u.get("index")) for u in unknowns] == list(range(len(inputs) + 1, len(svs) + 1))
    cfg = json.loads(z.read("resources/ecu.json"))
    assert cfg["guid"] == md.get("guid")
    assert cfg["faults"] == ["ignore-objects"] and cfg["margin_deg"] == 1
    assert [l["lid"] for l in cfg["lamps"]] == ["builtin:hd84_left", "builtin:hd84_right"]


def test_two_exports_are_byte_identical(tmp_path):
    export(tmp_path / "a.fmu")
    export(tmp_path / "b.fmu")
    assert filecmp.cmp(tmp_path / "a.fmu", tmp_path / "b.fmu", shallow=False)
    export(tmp_path / "c.fmu", "--no-bend")
    assert not filecmp.cmp(tmp_path / "a.fmu", tmp_path / "c.fmu", shallow=False)
