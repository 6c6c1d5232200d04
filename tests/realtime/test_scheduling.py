"""Real-time scheduling for the control thread: taken where allowed, given back, refused without privilege."""

import resource
import threading

import pytest

from mjx_badger.realtime import scheduling


def granted_in_a_thread(take, give_back) -> bool:
    """Whether `take()` is granted to a fresh thread of this process (given back at once)."""
    granted = []

    def probe():
        granted.append(take())
        if granted[0]:
            give_back()

    worker = threading.Thread(target=probe)
    worker.start()
    worker.join()
    return granted[0]


def fifo_privileged() -> bool:
    """Whether this process may enter SCHED_FIFO at the control priority: CAP_SYS_NICE or a high enough
    rtprio limit (what scheduling.py's docstring says it takes), read apart from the code under test."""
    cap_sys_nice = 1 << 23
    with open("/proc/self/status") as status:
        effective = next((int(line.split()[1], 16) for line in status if line.startswith("CapEff:")), 0)
    rtprio = resource.getrlimit(resource.RLIMIT_RTPRIO)[0]
    return bool(effective & cap_sys_nice) or rtprio == resource.RLIM_INFINITY or rtprio >= scheduling.CONTROL_PRIORITY


def test_realtime_scheduling_is_taken_where_allowed_and_given_back():
    if not fifo_privileged():
        pytest.skip("no CAP_SYS_NICE and an rtprio limit below the control priority: SCHED_FIFO is not allowed here")
    seen = {}

    def thread():
        seen["granted"] = scheduling.raise_to_realtime()
        seen["during"] = scheduling.is_realtime()
        scheduling.back_to_normal()
        seen["after"] = scheduling.is_realtime()

    worker = threading.Thread(target=thread)
    worker.start()
    worker.join()
    assert seen["granted"] and seen["during"] and not seen["after"]


def test_realtime_scheduling_is_refused_without_the_privilege():
    if fifo_privileged():
        pytest.skip("this process may enter SCHED_FIFO; the refusal needs an unprivileged process")
    assert not granted_in_a_thread(scheduling.raise_to_realtime, scheduling.back_to_normal)
    assert not scheduling.is_realtime()
