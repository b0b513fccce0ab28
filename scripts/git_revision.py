"""Write pygear/_git_revision.py from its template at build time (meson.build runs it).

    python scripts/git_revision.py SOURCE_DIR TEMPLATE OUTPUT

The revision is ``git describe --always --dirty --abbrev=12`` of SOURCE_DIR's own
repository, or "unknown" when SOURCE_DIR is no git checkout (an sdist): git is asked
only when SOURCE_DIR holds ``.git`` itself, with every ``GIT_*`` variable of the
environment dropped, so a repository around the build (a git hook's GIT_DIR, a virtual
environment or an unpacked sdist inside someone's repository) never answers.  OUTPUT is
rewritten only when its text changes, atomically, so a process importing the package
while another rebuilds it never reads half a file.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path


def revision(source: Path) -> str:
    if not (source / ".git").exists():
        return "unknown"
    environment = {k: v for k, v in os.environ.items() if not k.startswith("GIT_")}
    command = ["git", "-c", "safe.directory=*", "-C", str(source)]
    command += ["describe", "--always", "--dirty", "--abbrev=12"]
    try:
        described = subprocess.run(
            command, capture_output=True, text=True, env=environment, timeout=60
        )
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    text = described.stdout.strip()
    return text if described.returncode == 0 and text else "unknown"


def main(source: str, template: str, output: str) -> int:
    text = Path(template).read_text().replace("@GIT_REVISION@", revision(Path(source)))
    target = Path(output)
    if target.is_file() and target.read_text() == text:
        return 0
    handle, temporary = tempfile.mkstemp(prefix=f".{target.name}.", dir=target.parent)
    with os.fdopen(handle, "w") as stream:
        stream.write(text)
    os.chmod(temporary, 0o644)
    os.replace(temporary, target)
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
