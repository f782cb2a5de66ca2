"""The numerical libraries run on one thread unless the user chose otherwise (shapegen.threads)."""

import subprocess
import sys

from shapegen.threads import ONE_THREAD, one_thread_unless_chosen


def test_every_variable_is_set_to_one_when_none_is_given():
    environ = {"PATH": "/bin"}
    assert one_thread_unless_chosen(environ)
    assert environ == {"PATH": "/bin", **ONE_THREAD}


def test_a_users_choice_of_any_variable_leaves_all_of_them_alone():
    environ = {"OMP_NUM_THREADS": "4"}
    assert not one_thread_unless_chosen(environ)
    assert environ == {"OMP_NUM_THREADS": "4"}


def test_the_command_sets_them_for_its_own_process():
    # main() must set the variables before anything imports numpy, or OpenBLAS has already
    # started its threads: the command's own process is checked, its environment cleared.
    probe = (
        "import os, sys\n"
        "from shapegen.cli import main\n"
        "main(['rules'])\n"
        "import numpy\n"
        "print(os.environ.get('OPENBLAS_NUM_THREADS'))\n"
    )
    env = {"PATH": "/usr/bin:/bin"}
    done = subprocess.run(
        [sys.executable, "-c", probe], env=env, capture_output=True, text=True, check=True
    )
    assert done.stdout.splitlines()[-1] == "1"
