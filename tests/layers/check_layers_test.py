#!/usr/bin/env python3
"""The layering check (.ci/check_layers.py) on small trees made here: it passes what the table
allows, and fails, naming file:line, on a sideways or upward include, on a source file in a
folder the table does not name, and on a table with a cycle. Python 3 standard library only."""
import pathlib
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / ".ci" / "check_layers.py"

TABLE = """# Design

## Layout

### Layers

| folder | may include |
|---|---|
| `core/geom` | |
| `core/scene` | `core/geom` |
| `core/engine` | `core/scene` |
| `protocol` | `core` |
| `tests/fuzz` | `protocol` |
| `tests` | `protocol` |

## Something else

| `core/geom` | `core/engine` |
"""


class CheckLayers(unittest.TestCase):
    def setUp(self):
        self.root = pathlib.Path(tempfile.mkdtemp(prefix="check-layers-"))
        self.addCleanup(shutil.rmtree, self.root)
        self.write("docs/DESIGN.md", TABLE)
        self.write("core/geom/vec.h", "#pragma once\n")
        self.write("core/scene/scene.h", '#pragma once\n#include "core/geom/vec.h"\n')
        self.write("core/engine/engine.h", '#pragma once\n#include "core/scene/scene.h"\n')

    def write(self, path, text):
        target = self.root / path
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(text)

    def run_check(self):
        done = subprocess.run([sys.executable, str(SCRIPT), "--root", str(self.root)],
                              capture_output=True, text=True)
        return done.returncode, done.stdout + done.stderr

    def assert_passes(self):
        code, output = self.run_check()
        self.assertEqual(code, 0, output)

    def assert_reports(self, *lines):
        """Exit 1 and each of `lines` in the output, which is returned."""
        code, output = self.run_check()
        self.assertEqual(code, 1, output)
        for line in lines:
            self.assertIn(line, output)
        return output

    def test_downward_includes_pass(self):
        # Direct and transitive (engine -> scene -> geom), `core` for every core/ folder.
        self.write("core/engine/engine.cpp", '#include "core/engine/engine.h"\n#include "core/geom/vec.h"\n')
        self.write("protocol/scene_json.cpp", '#include "core/engine/engine.h"\n')
        self.assert_passes()

    def test_upward_include_is_named_with_file_and_line(self):
        self.write("core/geom/clip.h", '#pragma once\n\n#include "core/engine/engine.h"\n')
        self.assert_reports(
            "core/geom/clip.h:3: includes core/engine/engine.h: core/geom may not include core/engine")

    def test_sideways_include_between_top_level_folders_fails(self):
        self.write("protocol/json.h", "#pragma once\n")
        self.write("tests/fuzz/fuzz_json.cpp", '#include "protocol/json.h"\n')
        self.write("protocol/replay.cpp", '#include "tests/fuzz/fuzz_json.cpp"\n')
        output = self.assert_reports("protocol/replay.cpp:1:")
        self.assertNotIn("\ntests/fuzz/fuzz_json.cpp:", "\n" + output)

    def test_longest_folder_decides(self):
        # tests/fuzz is its own row: tests may not include it, though both start with tests/.
        self.write("tests/fuzz/support.h", "#pragma once\n")
        self.write("tests/engine_test.cpp", '#include "tests/fuzz/support.h"\n')
        self.assert_reports(
            "tests/engine_test.cpp:1: includes tests/fuzz/support.h: tests may not include tests/fuzz")

    def test_include_beside_the_file_resolves_to_its_folder(self):
        self.write("tests/fuzz/support.h", "#pragma once\n")
        self.write("tests/fuzz/fuzz_x.cpp", '#include "support.h"\n#include "third_party.h"\n')
        self.assert_passes()

    def test_file_outside_the_table_fails(self):
        self.write("scenegen/cubes.cpp", '#include "core/scene/scene.h"\n')
        self.assert_reports("scenegen/cubes.cpp: in no folder of the Layers table")

    def test_build_trees_are_not_read(self):
        self.write("build/tests/generated.cpp", '#include "core/engine/engine.h"\n')
        self.write("web_client/node_modules/x/y.h", '#include "core/engine/engine.h"\n')
        self.assert_passes()

    def test_cycle_in_the_table_fails(self):
        self.write("docs/DESIGN.md", TABLE.replace("| `core/geom` | |", "| `core/geom` | `core/engine` |", 1))
        code, output = self.run_check()
        self.assertNotEqual(code, 0, output)
        self.assertIn("cycle", output)


if __name__ == "__main__":
    unittest.main()
