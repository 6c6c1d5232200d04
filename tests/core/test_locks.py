"""One writer per output: a second run into the same results is refused, naming the running one."""

import os
import signal
import subprocess
import sys

from mjx_badger.cli.main import main
from mjx_badger.core import locks

TINY = ["train", "--approach", "jt-oef", "--task", "forward", "--steps", "300", "--chunk-steps", "100",
        "--warmup-steps", "100", "--eval-steps", "20", "--seeds", "2", "--quiet", "--no-tensorboard"]


def test_a_second_run_into_the_same_results_is_refused_naming_the_running_one(capsys, tmp_path):
    out = tmp_path / "jt-oef_crossq_forward.json"
    holder = subprocess.Popen([sys.executable, "-c", "import sys, time\nfrom mjx_badger.core import locks\n"
                               "with locks.hold(sys.argv[1]):\n    print('held', flush=True)\n    time.sleep(600)",
                               str(out)], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        assert main([*TINY, "--out", str(tmp_path)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and f"is being written by process {holder.pid}" in err, err
    finally:
        holder.send_signal(signal.SIGKILL)
        holder.wait()
    with locks.hold(out):  # the kernel dropped the killed holder's lock
        assert str(os.getpid()) in locks.path_for(out).read_text()
    assert not locks.path_for(out).exists()
