"""hdlamp batch k8s (docs/scale.md, "Kubernetes"): a plan as a Kubernetes Indexed Job.

There is no Kubernetes cluster here, so the manifest is checked as the API server would read it:
one YAML document, a batch/v1 Job whose every key is a field of the Job API of Kubernetes 1.29
(the first release with backoffLimitPerIndex on by default) — the tree walked against the schema
table below, written from the Kubernetes API reference — and whose values keep the API's rules
that the command relies on: completionMode Indexed, completions = the plan's tasks,
backoffLimitPerIndex with restartPolicy Never, one container running `hdlamp batch run ...
--index env` (the Job controller sets JOB_COMPLETION_INDEX in each pod of an Indexed Job), every
volume mount naming a volume. Then the refusals: a bad --name and other bad options (exit 2, the
option and what is expected), a plan whose header is wrong (exit 2, the file and line 1), a
missing plan."""
import json
import subprocess

import pytest
import yaml

# The Job API of Kubernetes 1.29, from the API reference (fields added later are left out, so
# that a manifest passing here is one that 1.29 reads):
#   Job, JobSpec, PodFailurePolicy:
#     https://kubernetes.io/docs/reference/kubernetes-api/workload-resources/job-v1/
#   PodTemplateSpec:
#     https://kubernetes.io/docs/reference/kubernetes-api/workload-resources/pod-template-v1/
#   PodSpec, Container, EnvVar, VolumeMount, ResourceRequirements:
#     https://kubernetes.io/docs/reference/kubernetes-api/workload-resources/pod-v1/
#   Volume, PersistentVolumeClaimVolumeSource, ConfigMapVolumeSource, KeyToPath:
#     https://kubernetes.io/docs/reference/kubernetes-api/config-and-storage-resources/volume/
#   ObjectMeta:
#     https://kubernetes.io/docs/reference/kubernetes-api/common-definitions/object-meta/
#   Quantity (resources' values, strings):
#     https://kubernetes.io/docs/reference/kubernetes-api/common-definitions/quantity/
# A field's type is: a type of this table; SCALAR (string, integer or boolean); STRING_MAP
# (string keys chosen by the user, scalar values: labels, annotations, limits, requests);
# ("list", T); or OTHER, a real field whose type the table does not describe: the walk refuses
# it, so that using one means describing it here first.
SCALAR, STRING_MAP, OTHER = "scalar", "string map", "other"

SCHEMA = {
    "Job": {
        "apiVersion": SCALAR, "kind": SCALAR, "metadata": "ObjectMeta", "spec": "JobSpec",
        # status is the cluster's to write, not a manifest's
    },
    "ObjectMeta": {
        "name": SCALAR, "generateName": SCALAR, "namespace": SCALAR, "labels": STRING_MAP,
        "annotations": STRING_MAP, "finalizers": ("list", SCALAR), "ownerReferences": OTHER,
        "creationTimestamp": SCALAR, "deletionGracePeriodSeconds": SCALAR,
        "deletionTimestamp": SCALAR, "generation": SCALAR, "managedFields": OTHER,
        "resourceVersion": SCALAR, "selfLink": SCALAR, "uid": SCALAR,
    },
    "JobSpec": {
        "template": "PodTemplateSpec", "parallelism": SCALAR, "completions": SCALAR,
        "completionMode": SCALAR, "backoffLimit": SCALAR, "activeDeadlineSeconds": SCALAR,
        "ttlSecondsAfterFinished": SCALAR, "suspend": SCALAR, "selector": OTHER,
        "manualSelector": SCALAR, "podFailurePolicy": "PodFailurePolicy",
        "podReplacementPolicy": SCALAR, "backoffLimitPerIndex": SCALAR,
        "maxFailedIndexes": SCALAR,
    },
    "PodFailurePolicy": {"rules": ("list", "PodFailurePolicyRule")},
    "PodFailurePolicyRule": {
        "action": SCALAR, "onExitCodes": "PodFailurePolicyOnExitCodesRequirement",
        "onPodConditions": ("list", "PodFailurePolicyOnPodConditionsPattern"),
    },
    "PodFailurePolicyOnExitCodesRequirement": {
        "containerName": SCALAR, "operator": SCALAR, "values": ("list", SCALAR),
    },
    "PodFailurePolicyOnPodConditionsPattern": {"status": SCALAR, "type": SCALAR},
    "PodTemplateSpec": {"metadata": "ObjectMeta", "spec": "PodSpec"},
    "PodSpec": {
        "containers": ("list", "Container"), "initContainers": ("list", "Container"),
        "ephemeralContainers": OTHER, "imagePullSecrets": OTHER, "enableServiceLinks": SCALAR,
        "os": OTHER, "volumes": ("list", "Volume"), "nodeSelector": STRING_MAP,
        "nodeName": SCALAR, "affinity": OTHER, "tolerations": OTHER, "schedulerName": SCALAR,
        "runtimeClassName": SCALAR, "priorityClassName": SCALAR, "priority": SCALAR,
        "preemptionPolicy": SCALAR, "topologySpreadConstraints": OTHER, "overhead": STRING_MAP,
        "restartPolicy": SCALAR, "terminationGracePeriodSeconds": SCALAR,
        "activeDeadlineSeconds": SCALAR, "readinessGates": OTHER, "hostname": SCALAR,
        "setHostnameAsFQDN": SCALAR, "subdomain": SCALAR, "hostAliases": OTHER,
        "dnsConfig": OTHER, "dnsPolicy": SCALAR, "hostNetwork": SCALAR, "hostPID": SCALAR,
        "hostIPC": SCALAR, "shareProcessNamespace": SCALAR, "serviceAccountName": SCALAR,
        "serviceAccount": SCALAR, "automountServiceAccountToken": SCALAR,
        "securityContext": OTHER, "schedulingGates": OTHER, "resourceClaims": OTHER,
        "hostUsers": SCALAR,
    },
    "Container": {
        "name": SCALAR, "image": SCALAR, "imagePullPolicy": SCALAR,
        "command": ("list", SCALAR), "args": ("list", SCALAR), "workingDir": SCALAR,
        "ports": OTHER, "env": ("list", "EnvVar"), "envFrom": OTHER,
        "volumeMounts": ("list", "VolumeMount"), "volumeDevices": OTHER,
        "resources": "ResourceRequirements", "resizePolicy": OTHER, "restartPolicy": SCALAR,
        "lifecycle": OTHER, "terminationMessagePath": SCALAR,
        "terminationMessagePolicy": SCALAR, "livenessProbe": OTHER, "readinessProbe": OTHER,
        "startupProbe": OTHER, "securityContext": OTHER, "stdin": SCALAR, "stdinOnce": SCALAR,
        "tty": SCALAR,
    },
    "EnvVar": {"name": SCALAR, "value": SCALAR, "valueFrom": OTHER},
    "VolumeMount": {
        "mountPath": SCALAR, "name": SCALAR, "mountPropagation": SCALAR, "readOnly": SCALAR,
        "subPath": SCALAR, "subPathExpr": SCALAR,
    },
    "ResourceRequirements": {"claims": OTHER, "limits": STRING_MAP, "requests": STRING_MAP},
    "Volume": {
        "name": SCALAR,
        "persistentVolumeClaim": "PersistentVolumeClaimVolumeSource",
        "configMap": "ConfigMapVolumeSource",
        **{source: OTHER for source in (
            "secret", "downwardAPI", "projected", "emptyDir", "hostPath", "ephemeral", "nfs",
            "csi", "iscsi", "fc", "rbd", "cephfs", "cinder", "glusterfs", "flexVolume",
            "flocker", "gitRepo", "awsElasticBlockStore", "azureDisk", "azureFile",
            "gcePersistentDisk", "photonPersistentDisk", "portworxVolume", "quobyte",
            "scaleIO", "storageos", "vsphereVolume")},
    },
    "PersistentVolumeClaimVolumeSource": {"claimName": SCALAR, "readOnly": SCALAR},
    "ConfigMapVolumeSource": {
        "name": SCALAR, "items": ("list", "KeyToPath"), "defaultMode": SCALAR,
        "optional": SCALAR,
    },
    "KeyToPath": {"key": SCALAR, "path": SCALAR, "mode": SCALAR},
}


def walk(node, typ, path, problems):
    """Appends to problems every key of node that is no field of typ, and every value of the
    wrong kind, with its path."""
    if typ == SCALAR:
        if not isinstance(node, (str, int, bool)):
            problems.append(f"{path}: expected a string, integer or boolean, found {node!r}")
        return
    if typ == STRING_MAP:
        if not isinstance(node, dict) or not all(
                isinstance(k, str) and isinstance(v, (str, int, bool)) for k, v in node.items()):
            problems.append(f"{path}: expected a map of strings, found {node!r}")
        return
    if isinstance(typ, tuple):
        if not isinstance(node, list):
            problems.append(f"{path}: expected a list, found {node!r}")
            return
        for i, item in enumerate(node):
            walk(item, typ[1], f"{path}[{i}]", problems)
        return
    if not isinstance(node, dict):
        problems.append(f"{path}: expected a {typ} object, found {node!r}")
        return
    for key, value in node.items():
        field = SCHEMA[typ].get(key)
        if field is None:
            problems.append(f"{path}.{key}: no field '{key}' in {typ}")
        elif field == OTHER:
            problems.append(f"{path}.{key}: a field of {typ} this test's table does not describe")
        else:
            walk(value, field, f"{path}.{key}", problems)


def write_plan(path, tasks, lines=None):
    header = {"plan": "hdlamp batch plan", "version": 1, "tasks": tasks,
              "spec": "/abs/spec.json"}
    with open(path, "w") as f:
        f.write(json.dumps(header) + "\n")
        for i in range(tasks if lines is None else lines):
            f.write(json.dumps({"index": i, "id": f"sil/s{i}/reference/none", "kind": "sil",
                                "scenario": f"/abs/s{i}.json", "ecu": "reference",
                                "fault": "", "config": "", "set": []}) + "\n")
    return path


def k8s(hdlamp, *args):
    return subprocess.run([hdlamp, "batch", "k8s", *map(str, args)], capture_output=True,
                          text=True, timeout=30)


def manifest(hdlamp, *args):
    r = k8s(hdlamp, *args)
    assert r.returncode == 0, r.stderr
    docs = list(yaml.safe_load_all(r.stdout))
    assert len(docs) == 1, f"{len(docs)} YAML documents"
    return docs[0], r.stdout


@pytest.fixture
def plan(tmp_path):
    return write_plan(tmp_path / "plan.jsonl", 5)


def check_job(job):
    problems = []
    walk(job, "Job", "Job", problems)
    assert not problems, "\n".join(problems)
    assert job["apiVersion"] == "batch/v1" and job["kind"] == "Job"
    spec = job["spec"]
    pod = spec["template"]["spec"]
    # backoffLimitPerIndex: only with completionMode Indexed and restartPolicy Never
    assert spec["completionMode"] == "Indexed"
    assert pod["restartPolicy"] == "Never"
    names = {v["name"] for v in pod.get("volumes", [])}
    assert len(names) == len(pod.get("volumes", []))
    for c in pod["containers"]:
        for m in c.get("volumeMounts", []):
            assert m["name"] in names, f"{m['name']} mounted but no such volume"
        for q in list(c["resources"]["requests"].values()) + list(c["resources"]["limits"].values()):
            assert isinstance(q, str), f"quantity {q!r} is not a string"
    containers = {c["name"] for c in pod["containers"]}
    for rule in spec.get("podFailurePolicy", {}).get("rules", []):
        if "onExitCodes" in rule:
            assert rule["onExitCodes"]["containerName"] in containers
            assert 0 not in rule["onExitCodes"]["values"]
        if rule["action"] == "FailIndex":
            assert "backoffLimitPerIndex" in spec
    return spec, pod


def test_defaults(hdlamp, plan):
    job, text = manifest(hdlamp, plan)
    spec, pod = check_job(job)
    assert text.startswith("# hdlamp batch k8s")
    assert "kubectl apply -f" in text and "hdlamp batch merge /results" in text
    assert job["metadata"]["name"] == "hdlamp-batch"
    assert spec["completions"] == 5
    assert spec["parallelism"] == 2
    assert spec["backoffLimitPerIndex"] == 1
    assert "maxFailedIndexes" not in spec and "activeDeadlineSeconds" not in pod
    assert len(pod["containers"]) == 1
    c = pod["containers"][0]
    assert c["image"].startswith("hdlamp:")
    cmd = c["command"]
    assert cmd[:4] == ["hdlamp", "batch", "run", "/results/plan.jsonl"]
    i = cmd.index("--index")
    assert cmd[i + 1] == "env"
    assert cmd[cmd.index("--out") + 1] == "/results"
    assert "env" not in c  # JOB_COMPLETION_INDEX comes from the Job controller
    assert c["resources"] == {"requests": {"cpu": "1", "memory": "2Gi"},
                              "limits": {"cpu": "1", "memory": "2Gi"}}
    assert c["volumeMounts"] == [{"name": "results", "mountPath": "/results"}]
    assert pod["volumes"] == [{"name": "results",
                               "persistentVolumeClaim": {"claimName": "hdlamp-results"}}]
    # exit 2 (bad input) and 3 (verdict failed) are results: no retry (tools/batch.h)
    rules = spec["podFailurePolicy"]["rules"]
    assert {"action": "FailIndex", "onExitCodes": {"containerName": c["name"], "operator": "In",
                                                   "values": [2, 3]}} in rules


def test_every_option(hdlamp, plan, tmp_path):
    out = tmp_path / "job.yaml"
    image = 'registry.example:5000/hdl"amp\\x@sha256:0123'
    r = k8s(hdlamp, plan, "--out", out, "--name", "adb-night-7", "--image", image,
            "--parallelism", 40, "--backoff-limit-per-index", 0, "--max-failed-indexes", 3,
            "--results-claim", "results.lab-1", "--plan-configmap", "adb-plan",
            "--cpu", "500m", "--memory", "1536Mi", "--active-deadline-s", 7200)
    assert r.returncode == 0, r.stderr
    assert r.stdout == ""
    docs = list(yaml.safe_load_all(out.read_text()))
    assert len(docs) == 1
    job = docs[0]
    spec, pod = check_job(job)
    assert job["metadata"]["name"] == "adb-night-7"
    assert spec["parallelism"] == 40 and spec["backoffLimitPerIndex"] == 0
    assert spec["maxFailedIndexes"] == 3 and spec["completions"] == 5
    assert pod["activeDeadlineSeconds"] == 7200
    c = pod["containers"][0]
    assert c["image"] == image  # quoted: the quote and the backslash come back as they were
    assert c["command"][3] == "/plan/plan.jsonl"
    assert c["resources"]["limits"] == {"cpu": "500m", "memory": "1536Mi"}
    assert {"name": "plan", "mountPath": "/plan", "readOnly": True} in c["volumeMounts"]
    vols = {v["name"]: v for v in pod["volumes"]}
    assert vols["results"]["persistentVolumeClaim"] == {"claimName": "results.lab-1"}
    assert vols["plan"]["configMap"] == {
        "name": "adb-plan", "items": [{"key": "plan.jsonl", "path": "plan.jsonl"}]}
    assert "kubectl create configmap adb-plan --from-file=plan.jsonl=" in out.read_text()
    # the same manifest as on stdout, but for the file's name in the comments
    same = k8s(hdlamp, plan, "--name", "adb-night-7", "--image", image, "--parallelism", 40,
               "--backoff-limit-per-index", 0, "--max-failed-indexes", 3, "--results-claim",
               "results.lab-1", "--plan-configmap", "adb-plan", "--cpu", "500m", "--memory",
               "1536Mi", "--active-deadline-s", 7200)
    assert f"kubectl apply -f {out}\n" in out.read_text()
    assert same.stdout == out.read_text().replace(str(out), "MANIFEST.yaml")


def test_count_is_the_header(hdlamp, tmp_path):
    """The header's count is the array's size, the lines are not read; over 10^5 tasks
    Kubernetes requires maxFailedIndexes, at most 10^4."""
    big = write_plan(tmp_path / "big.jsonl", 150000, lines=2)
    r = k8s(hdlamp, big)
    assert r.returncode == 2
    assert "--max-failed-indexes" in r.stderr and "100000" in r.stderr
    assert k8s(hdlamp, big, "--max-failed-indexes", 20000).returncode == 2
    job, _ = manifest(hdlamp, big, "--max-failed-indexes", 100)
    check_job(job)
    assert job["spec"]["completions"] == 150000 and job["spec"]["maxFailedIndexes"] == 100


@pytest.mark.parametrize("name", ["Hdlamp", "hdlamp_batch", "-batch", "batch-", "a.b", "",
                                  "x" * 64, "ab cd"])
def test_bad_name(hdlamp, plan, name):
    r = k8s(hdlamp, plan, "--name", name)
    assert r.returncode == 2, r.stdout
    assert r.stdout == ""
    assert "--name" in r.stderr and "DNS-1123 label" in r.stderr, r.stderr


def test_longest_name(hdlamp, plan):
    job, _ = manifest(hdlamp, plan, "--name", "a" + "-" * 61 + "9")
    assert len(job["metadata"]["name"]) == 63


@pytest.mark.parametrize("args,option", [
    (["--parallelism", "0"], "--parallelism"),
    (["--parallelism", "100001"], "--parallelism"),
    (["--parallelism", "-1"], "--parallelism"),
    (["--backoff-limit-per-index", "x"], "--backoff-limit-per-index"),
    (["--max-failed-indexes", "6"], "--max-failed-indexes"),  # more than the 5 tasks
    (["--results-claim", "Results"], "--results-claim"),
    (["--plan-configmap", "plan..x"], "--plan-configmap"),
    (["--cpu", "0"], "--cpu"),
    (["--cpu", "-1"], "--cpu"),
    (["--memory", "2 Gi"], "--memory"),
    (["--memory", "2GB"], "--memory"),
    (["--image", "hdlamp 0.1"], "--image"),
    (["--image", "hdlamp\n0.1"], "--image"),
    (["--active-deadline-s", "0"], "--active-deadline-s"),
])
def test_bad_options(hdlamp, plan, args, option):
    r = k8s(hdlamp, plan, *args)
    assert r.returncode == 2, r.stdout
    assert r.stdout == ""
    assert option in r.stderr and "expected" in r.stderr, r.stderr


@pytest.mark.parametrize("first,what", [
    ('{"plan": "hdlamp batch plan", "version": 1', "not JSON"),
    ('["hdlamp batch plan", 1, 3]', "not a JSON object"),
    ('{"plan": "something else", "version": 1, "tasks": 3}', '"plan"'),
    ('{"plan": "hdlamp batch plan", "version": 2, "tasks": 3}', '"version" is 2'),
    ('{"plan": "hdlamp batch plan", "version": 1}', '"tasks"'),
    ('{"plan": "hdlamp batch plan", "version": 1, "tasks": -1}', '"tasks"'),
    ('{"plan": "hdlamp batch plan", "version": 1, "tasks": "3"}', '"tasks"'),
    ('{"index": 0, "id": "sil/x", "kind": "sil"}', '"plan"'),
    ("", "empty"),
])
def test_bad_header(hdlamp, tmp_path, first, what):
    path = tmp_path / "bad.jsonl"
    path.write_text(first + ("\n" if first else "") + '{"index": 0}\n' * bool(first))
    r = k8s(hdlamp, path)
    assert r.returncode == 2, r.stdout
    assert r.stdout == ""
    assert f"{path}:1:" in r.stderr, r.stderr
    assert what in r.stderr and "expected the plan's header" in r.stderr, r.stderr


def test_plan_without_tasks(hdlamp, tmp_path):
    r = k8s(hdlamp, write_plan(tmp_path / "empty.jsonl", 0))
    assert r.returncode == 2 and "no tasks" in r.stderr, r.stderr


def test_missing_plan(hdlamp, tmp_path):
    path = tmp_path / "nowhere.jsonl"
    r = k8s(hdlamp, path)
    assert r.returncode == 2
    assert r.stdout == ""
    assert str(path) in r.stderr and "No such file" in r.stderr, r.stderr


def test_usage(hdlamp, plan):
    r = k8s(hdlamp, "--help")
    assert r.returncode == 0
    for opt in ("--out", "--name", "--image", "--parallelism", "--backoff-limit-per-index",
                "--max-failed-indexes", "--results-claim", "--plan-configmap", "--cpu",
                "--memory", "--active-deadline-s"):
        assert opt in r.stdout, opt
    assert k8s(hdlamp).returncode == 2
    assert k8s(hdlamp, plan, plan).returncode == 2
    assert k8s(hdlamp, plan, "--no-such-option").returncode == 2
    top = subprocess.run([hdlamp, "batch", "--help"], capture_output=True, text=True, timeout=30)
    assert top.returncode == 0 and "hdlamp batch k8s" in top.stdout
    assert subprocess.run([hdlamp, "batch", "nope"], capture_output=True,
                          timeout=30).returncode == 2


def test_out_unwritable(hdlamp, plan, tmp_path):
    r = k8s(hdlamp, plan, "--out", tmp_path / "no" / "dir" / "job.yaml")
    assert r.returncode == 1
    assert "job.yaml" in r.stderr
