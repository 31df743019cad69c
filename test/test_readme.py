"""The README is a reference: every topic, service, parameter, command and scene it lists exists in the code, and
the code has none it leaves out. Read from the README's tables and lists, held against the code's own lists (the
CLI's parser, the node's parameter table, the publishers' topic types, the services the node creates, the scene
registry); no ROS is started. Also: its links resolve, its make targets exist, and no line is over 120 characters.

Each check is a function of the README's text, so the last test plants a wrong name in each list and expects the
check to name it: a check that can no longer fail is noticed."""
import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
README = REPO / "README.md"


# ---- reading the README -------------------------------------------------------------------------------------

def section(text, title):
    """The lines of the section whose heading is `title` (any level), up to the next heading of the same or a higher
    level."""
    lines = text.splitlines()
    for i, line in enumerate(lines):
        m = re.match(r"(#+) (.*)$", line)
        if m and m.group(2).strip() == title:
            level = len(m.group(1))
            out = []
            for rest in lines[i + 1:]:
                n = re.match(r"(#+) ", rest)
                if n and len(n.group(1)) <= level:
                    break
                out.append(rest)
            return out
    raise AssertionError(f"README.md has no section {title!r}")


def tables(lines):
    """Every markdown table in `lines`: (header cells, [row cells])."""
    found, current = [], None
    for line in lines + [""]:
        if line.startswith("|"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if current is None:
                current = (cells, [])
            elif not all(re.fullmatch(r":?-+:?", c) for c in cells):
                current[1].append(cells)
        elif current is not None:
            found.append(current)
            current = None
    return found


def table(lines, first_header):
    """The rows of the table whose first header cell is `first_header`."""
    for header, rows in tables(lines):
        if header[0] == first_header:
            return rows
    raise AssertionError(f"no table headed {first_header!r}")


def code(cell):
    """The first `...` span of a cell."""
    m = re.search(r"`([^`]*)`", cell)
    assert m, f"no `name` in {cell!r}"
    return m.group(1)


def node_tables(text):
    lines = section(text, "The ROS 2 node")
    return table(lines, "topic"), table(lines, "service"), table(lines, "parameter")


def readme_commands(text):
    """The commands the command-line section lists, one per line: `sph-fsi NAME ...`."""
    return [m.group(1) for line in section(text, "Command line")
            for m in [re.match(r"- `sph-fsi ([a-z][a-z-]*)", line)] if m]


def readme_scenes(text):
    return [code(row[0]) for row in table(section(text, "Scenes and keys"), "scene")]


# ---- the code's own lists -----------------------------------------------------------------------------------

def cli_commands():
    from sph_fsi.cli import build_parser
    usage = build_parser().format_usage()
    m = re.search(r"\{([a-z,-]+)\}", usage)
    assert m, usage
    return m.group(1).split(",")


def builtin_scene_names():
    from sph_fsi_core.scene import builtin_scenes
    return set(builtin_scenes())


def node_services():
    """{service name: type} the node creates (node.py's create_service calls)."""
    source = (REPO / "sph_fsi" / "node.py").read_text()
    return dict((name, kind) for kind, name in re.findall(r'create_service\((\w+), "([^"]+)"', source))


def fixed_topics():
    """{topic: message class name} of the topics every node has (publishing.py's create_publisher calls)."""
    source = (REPO / "sph_fsi" / "publishing.py").read_text()
    return dict((name, kind) for kind, name in re.findall(r'create_publisher\((\w+), "(/[^"]+)"', source))


def scene_topics():
    """{topic as the README names it: message type} of the scene-dependent topics (sph_fsi.points)."""
    from sph_fsi.points import PART_TYPES, PROBE_QUANTITIES, QUANTITY_TYPES, TOPIC_TYPES
    from sph_fsi.publishing import COMMAND_TOPICS
    topics = {f"~/{name}": kind for name, kind in TOPIC_TYPES.items()}
    quantities = {q for qs in PROBE_QUANTITIES.values() for q in qs}
    topics.update({f"~/probes/<name>/{q}": QUANTITY_TYPES[q] for q in quantities})
    topics.update({f"~/parts/<name>/{what}": kind for what, kind in PART_TYPES.items() if what not in COMMAND_TOPICS})
    return topics


# ---- the checks: each returns what is wrong, as lines -------------------------------------------------------

def check_commands(text):
    listed, known = readme_commands(text), cli_commands()
    return ([f"command {c!r} is not an sph-fsi subcommand" for c in listed if c not in known]
            + [f"subcommand {c!r} is not in the README" for c in known if c not in listed])


def check_scenes(text):
    listed, known = readme_scenes(text), builtin_scene_names()
    wrong = [f"scene {s!r} is not a built-in scene" for s in listed if s not in known]
    wrong += [f"built-in scene {s!r} is not in the README" for s in sorted(known - set(listed))]
    wrong += [f"config file {p} does not exist" for p in re.findall(r"`(config/[\w./-]+\.yaml)`", text)
              if not (REPO / p).is_file()]
    return wrong


def check_topics(text):
    rows, _, _ = node_tables(text)
    listed = {code(row[0]): code(row[1]) for row in rows}
    known = scene_topics()
    fixed = fixed_topics()
    wrong = []
    for topic, kind in listed.items():
        if topic in known:
            if kind != known[topic]:
                wrong.append(f"topic {topic}: the README says {kind}, the code {known[topic]}")
        elif topic in fixed:
            if kind.rsplit("/", 1)[-1] != fixed[topic]:
                wrong.append(f"topic {topic}: the README says {kind}, the code publishes {fixed[topic]}")
        else:
            wrong.append(f"topic {topic!r} is not published by the node")
    wrong += [f"topic {t} is not in the README" for t in sorted(set(known) | set(fixed)) if t not in listed]
    return wrong


def check_services(text):
    _, rows, _ = node_tables(text)
    listed = {code(row[0]): code(row[1]) for row in rows}
    known = node_services()
    wrong = [f"service {s!r} is not created by the node" for s in listed if s not in known]
    wrong += [f"service {s}: the README says {kind}, the node creates a {known[s]}" for s, kind in listed.items()
              if s in known and kind.rsplit("/", 1)[-1] != known[s]]
    wrong += [f"service {s} is not in the README" for s in known if s not in listed]
    return wrong


def check_parameters(text):
    from sph_fsi.parameters import NODE_PARAMS
    _, _, rows = node_tables(text)
    wrong = []
    listed = []
    for row in rows:
        name, default = code(row[0]), row[1].strip("`")
        listed.append(name)
        if name not in NODE_PARAMS:
            wrong.append(f"parameter {name!r} is not one of the node's")
            continue
        value = NODE_PARAMS[name].default
        same = (default in ("''", "") and value == "") or default == str(value) or (
            isinstance(value, bool) and default == str(value).lower())
        if not same and isinstance(value, (int, float)) and not isinstance(value, bool):
            try:
                same = float(default) == float(value)
            except ValueError:
                same = False
        if not same:
            wrong.append(f"parameter {name}: the README's default {default!r}, the code's {value!r}")
    wrong += [f"parameter {p} is not in the README" for p in NODE_PARAMS if p not in listed]
    return wrong


def check_links(text):
    """Relative links ([x](path), [x]: path) resolve to files or folders of the repository."""
    targets = re.findall(r"\]\(([^)\s]+)\)", text) + re.findall(r"^\[[^\]]+\]: (\S+)", text, flags=re.M)
    return [f"link {t} does not resolve" for t in targets
            if not re.match(r"[a-z]+://", t) and not (REPO / t.split("#")[0]).exists()]


def check_make_targets(text):
    phony = re.search(r"^\.PHONY: (.*)$", (REPO / "Makefile").read_text(), flags=re.M).group(1).split()
    return [f"make target {t!r} is not in the Makefile" for t in set(re.findall(r"`make ([a-z][a-z-]*)", text))
            if t not in phony]


def readme_list_keys(text):
    """The lines of the table of the lists' keys (its header: `| list |`) in the scenes' section."""
    lines = section(text, "Scenes and keys")
    start = next((i for i, line in enumerate(lines) if line.startswith("| list |")), None)
    assert start is not None, "README.md's 'Scenes and keys' has no table of the lists' keys (| list | ...)"
    block = []
    for line in lines[start:]:
        if not line.startswith("|"):
            break
        block.append(line)
    return block


def check_list_keys(text):
    """The table of every part, probe and judge key is the declarations' (geometry/parts.py reference_table)."""
    from sph_fsi_core.geometry.parts import reference_table
    listed, known = readme_list_keys(text), reference_table()
    wrong = [f"row {row!r} is not the declarations' (sph_fsi_core/geometry/parts.py)" for row in listed
             if row not in known]
    wrong += [f"row {row!r} of the declarations is not in the README" for row in known if row not in listed]
    if not wrong and listed != known:
        wrong.append("the rows are not in the declarations' order")
    if wrong:
        wrong.append("the table, as reference_table() makes it:\n" + "\n".join(known))
    return wrong


def check_line_lengths(text):
    return [f"line {i} is {len(line)} characters" for i, line in enumerate(text.splitlines(), 1) if len(line) > 120]


CHECKS = [check_commands, check_scenes, check_topics, check_services, check_parameters, check_links,
          check_make_targets, check_line_lengths, check_list_keys]


@pytest.mark.parametrize("check", CHECKS, ids=lambda c: c.__name__)
def test_the_readme_agrees_with_the_code(check):
    wrong = check(README.read_text())
    assert not wrong, "README.md against the code:\n" + "\n".join(wrong)


def test_the_readme_lists_something_in_each_table():
    text = README.read_text()
    topics, services, parameters = node_tables(text)
    assert len(topics) >= 7 and len(services) >= 4 and len(parameters) >= 10
    assert len(readme_commands(text)) >= 8 and len(readme_scenes(text)) >= 10


# a wrong name planted where each check reads: (check, text replaced, replacement, what the complaint names)
PLANTS = [
    (check_commands, "- `sph-fsi scenes`", "- `sph-fsi scenez`", "scenez"),
    (check_scenes, "| `dam_break` |", "| `dam_brake` |", "dam_brake"),
    (check_scenes, "`config/spheric2_dam_break.yaml`", "`config/spheric3_dam_break.yaml`", "spheric3"),
    (check_topics, "| `~/walls` |", "| `~/wallz` |", "wallz"),
    (check_topics, "`sensor_msgs/msg/FluidPressure`", "`std_msgs/msg/Float64`", "pressure"),
    (check_services, "| `~/pause` |", "| `~/paws` |", "paws"),
    (check_services, "| `~/pause` | `std_srvs/srv/SetBool` |", "| `~/pause` | `std_srvs/srv/Trigger` |", "pause"),
    (check_parameters, "| `frame_id` |", "| `frame_idd` |", "frame_idd"),
    (check_parameters, "| `publish_period` | 0.005 |", "| `publish_period` | 0.05 |", "publish_period"),
    (check_links, "(docs/method.md)", "(docs/methods.md)", "methods.md"),
    (check_make_targets, "`make test-fast`", "`make test-faster`", "test-faster"),
    (check_list_keys, "| `parts` | shape box | `size` (m) required |", "| `parts` | shape box | `sise` (m) required |",
     "sise"),
    (check_list_keys, "`lift_velocity` (m/s) = [0, 0, 1]", "`lift_velocity` (m/s) = [0, 0, 2]", "lift_velocity"),
]


@pytest.mark.parametrize("check, old, new, named", PLANTS, ids=[p[3] for p in PLANTS])
def test_each_check_names_a_planted_wrong_name(check, old, new, named):
    text = README.read_text()
    assert old in text, f"the plant's anchor {old!r} is gone from README.md: update PLANTS"
    wrong = check(text.replace(old, new, 1))
    assert any(named in line for line in wrong), wrong


def test_every_error_in_the_answers_table_is_the_reports():
    """Issue 50: every number in the README comes from the report. Each value of the error column of "What the
    default's answers are worth" appears in docs/validation/REPORT.md with its unit (% or mm), signed as there."""
    report = (REPO / "docs" / "validation" / "REPORT.md").read_text()
    rows = table(section(README.read_text(), "What the default's answers are worth"), "case")
    assert len(rows) >= 12
    for row in rows:
        values = re.findall(r"[-+]?\d+\.\d+", row[2])
        assert values, row
        for value in values:
            assert f"{value} %" in report or f"{value} mm" in report, (row[0], value)
