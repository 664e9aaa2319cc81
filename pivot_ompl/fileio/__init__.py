"""The file boundary: bounded, strict reading of YAML/JSON inputs and atomic output writing.

Reading (scene YAML, ``pivot-plan/1`` JSON): at most :data:`MAX_FILE_BYTES`, UTF-8 only,
duplicate keys refused, YAML aliases expanded to at most :data:`MAX_NODES` nodes (a "billion
laughs" file is refused in milliseconds), nesting deeper than the parser's recursion refused,
integers too long for a float refused. Every failure is an :class:`~pivot_ompl.errors.InputError`
of the caller's kind naming the file.

Every input is first a path (``str`` or ``os.PathLike``) to a regular file
(:func:`regular_file`): a FIFO, a socket or a device is refused at once, never read (reading
could block forever).

Writing: :func:`atomic_outputs` yields a short temporary path next to each target; the targets
are replaced (``os.replace``) only when the ``with`` block succeeds, so a failed or interrupted
run never destroys an existing file and a run's outputs are written all or nothing. Files are
created with the process's umask (no mode of their own). :func:`check_output` refuses, before
any work, a target that is a directory, that is one of the run's input files, whose names are
too long for its file system, or whose folder is a file.

Modules: :mod:`~pivot_ompl.fileio.reading` (paths, text, JSON),
:mod:`~pivot_ompl.fileio.yaml_strict` (YAML; plain documents built by
:mod:`~pivot_ompl.fileio.yaml_plain`), :mod:`~pivot_ompl.fileio.outputs` (writing).
"""

from pivot_ompl.fileio.outputs import (
    MAX_NAME,
    MAX_PATH,
    MAX_STEM,
    atomic_output,
    atomic_outputs,
    check_output,
    file_stem,
)
from pivot_ompl.fileio.reading import (
    MAX_FILE_BYTES,
    input_path,
    load_json,
    read_text,
    regular_file,
)
from pivot_ompl.fileio.yaml_strict import (
    MAX_NODES,
    POLL_NODES,
    UNWIND_SHARE,
    load_yaml,
    parse_deadline,
)

__all__ = [
    "MAX_FILE_BYTES", "MAX_NAME", "MAX_NODES", "MAX_PATH", "MAX_STEM", "POLL_NODES",
    "UNWIND_SHARE", "atomic_output", "atomic_outputs", "check_output", "file_stem",
    "input_path", "load_json", "load_yaml", "parse_deadline", "read_text", "regular_file",
]
