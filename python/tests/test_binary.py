"""mimo_ta.binary.find_mimo_bin: the environment's scripts directory first, then the user
scheme's, then the PATH (as uv's shim finds uv)."""

import os
import stat
import tempfile
import unittest
from pathlib import Path
from unittest import mock

from mimo_ta import binary


def executable(d: Path) -> str:
    p = d / "mimo"
    p.write_text("#!/bin/sh\n")
    p.chmod(p.stat().st_mode | stat.S_IXUSR)
    return str(p)


class FindMimoTest(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        root = Path(self.tmp.name)
        self.scripts, self.user, self.on_path = root / "env-bin", root / "user-bin", root / "path-bin"
        for d in (self.scripts, self.user, self.on_path):
            d.mkdir()

    def tearDown(self):
        self.tmp.cleanup()

    def find(self):
        real = binary.sysconfig.get_path

        def get_path(name, scheme=None, **kw):
            if name != "scripts":
                return real(name, scheme, **kw) if scheme else real(name, **kw)
            return str(self.user if scheme else self.scripts)

        with mock.patch.object(binary.sysconfig, "get_path", get_path), \
                mock.patch.dict(os.environ, {"PATH": str(self.on_path)}):
            return binary.find_mimo_bin()

    def test_the_environment_first_then_the_user_scheme_then_the_path(self):
        on_path = executable(self.on_path)
        self.assertEqual(self.find(), on_path)
        user = executable(self.user)
        self.assertEqual(self.find(), user)
        env = executable(self.scripts)
        self.assertEqual(self.find(), env)

    def test_none_anywhere_says_where_it_looked(self):
        with self.assertRaises(FileNotFoundError) as e:
            self.find()
        self.assertIn(str(self.scripts), str(e.exception))
        self.assertIn("PATH", str(e.exception))

    def test_a_file_that_is_not_executable_is_not_the_binary(self):
        (self.scripts / "mimo").write_text("not a program\n")
        on_path = executable(self.on_path)
        self.assertEqual(self.find(), on_path)


if __name__ == "__main__":
    unittest.main()
