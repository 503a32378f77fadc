# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""The heartbeat asks every instance at once, and brings back what its host started again."""

import threading
import time

from conftest import wait_until

from robmosys_runtime.system import drift, heartbeat
from robmosys_runtime.system.heartbeat import Heartbeat


class Instances:
    """A system's activation as the heartbeat sees it: states, answers, restarts."""

    def __init__(self, answers, delay=0.0, failed=None) -> None:
        self.answers = dict(answers)
        self.delay = delay
        self.restarted = []
        self.failed = dict(failed or {})
        self.asked = []
        #: told active by their process, their get_state not discovered yet
        self.discovered_later = set()
        #: left inactive by the system's mode (none here)
        self.held = set()

    def running(self) -> bool:
        return False

    def driving(self, name) -> bool:
        return False

    def states(self):
        states = dict.fromkeys(self.answers, 'active')
        states.update(dict.fromkeys(self.failed, 'failed'))
        return states

    def failures(self):
        return dict(self.failed)

    def probe(self, name, timeout):
        self.asked.append((name, time.monotonic()))
        if self.answers[name] is None:
            time.sleep(timeout)
        time.sleep(self.delay)
        return self.answers[name]

    def discovering(self, name) -> bool:
        return name in self.discovered_later

    def restart(self, *names) -> None:
        self.restarted.append(names)

    def instance_failed(self, name, why, report=True) -> None:
        if not report or name not in self.failed:
            self.failed[name] = why

    def recovered(self, name):
        self.failed.pop(name, None)
        return []


def _beat(instances, silent, here=(), respawn=()):
    described = {n: {'respawn': n in respawn} for n in instances.answers}
    return Heartbeat(instances, 0.2, silent, described, set(here), lambda: True)


def test_silent_instances_are_reported_after_three_heartbeats_however_many(monkeypatch):
    said = []
    monkeypatch.setattr(heartbeat, 'say', lambda level, text: said.append((level, text)))
    names = [f'node{n}' for n in range(6)]
    instances = Instances(dict.fromkeys(names, None))
    silent = {}
    stopping = threading.Event()
    beating = threading.Thread(target=_beat(instances, silent).run, args=(stopping,))
    start = time.monotonic()
    beating.start()
    while len(silent) < len(names) and time.monotonic() - start < 10:
        time.sleep(0.01)
    took = time.monotonic() - start
    stopping.set()
    beating.join(5)
    assert sorted(silent) == names
    assert set(silent.values()) == {'no answer for 0.6 s'}
    # asked at once, not one after the other: six silent instances do not take six times
    # as long (0.2 s each would be 3.6 s for three heartbeats)
    assert took < 3.0, took
    assert ('error', 'instance node0 does not answer (heartbeat): no answer for 0.6 s') in said


def test_an_instance_whose_service_is_still_discovered_is_not_silent_until_it_is():
    instances = Instances({'told': None, 'asked': None})
    instances.discovered_later = {'told'}
    silent = {}
    beat = _beat(instances, silent)
    for _ in range(3):
        beat.heard({'told': None, 'asked': None})
    # its process said it is active; its get_state is still to be discovered
    assert list(silent) == ['asked']
    instances.discovered_later.clear()
    for _ in range(3):
        beat.heard({'told': None, 'asked': None})
    assert sorted(silent) == ['asked', 'told']


def test_what_answers_again_is_told_and_what_came_back_is_brought_up_together(monkeypatch):
    said = []
    monkeypatch.setattr(heartbeat, 'say', lambda level, text: said.append((level, text)))
    monkeypatch.setattr(drift, 'say', lambda level, text: said.append((level, text)))
    instances = Instances({'sender': 'unconfigured', 'server': 'unconfigured',
                           'receiver': 'active', 'local': 'unconfigured'})
    silent = {'sender': 'no answer for 3 s', 'server': 'no answer for 3 s',
              'receiver': 'no answer for 3 s'}
    beat = _beat(instances, silent, here={'local'})
    beat.heard(instances.answers)
    # one bring-up for both: each would bring their successors up too
    assert instances.restarted == [('sender', 'server')]
    assert silent == {}
    # an instance this manager started, unconfigured: cleaned up behind its back
    assert instances.failed == {'local': 'is unconfigured, not active'}
    assert ('error', 'instance local is unconfigured, not active (heartbeat)') in said
    assert ('info', 'instance receiver answers again (heartbeat)') in said
    assert ('info', 'instance sender came back (heartbeat): bringing it up') in said


def test_an_instance_marked_respawn_comes_back_here_too():
    beat = _beat(Instances({'a': None, 'b': None}), {}, here={'a', 'b'}, respawn={'a'})
    assert beat.restartable('a') and not beat.restartable('b')


def test_a_failed_instance_of_another_host_comes_back_once_its_process_went(monkeypatch):
    monkeypatch.setattr(heartbeat, 'say', lambda level, text: None)
    instances = Instances({'remote': 'unconfigured', 'local': None},
                          failed={'remote': 'failed to configure (it is unconfigured)'})
    beat = _beat(instances, {}, here={'local'})
    # its configure failed: it answers unconfigured all along, and is not retried
    beat.heard({'remote': 'unconfigured'}, failed={'remote'})
    assert instances.restarted == []
    # its host's bringup was killed (no answer), then started again
    beat.heard({'remote': None}, failed={'remote'})
    beat.heard({'remote': 'unconfigured'}, failed={'remote'})
    assert instances.restarted == [('remote',)]


def test_a_failure_clears_once_the_instance_is_active_again_whatever_repaired_it(monkeypatch):
    said = []
    monkeypatch.setattr(heartbeat, 'say', lambda level, text: said.append((level, text)))
    monkeypatch.setattr(drift, 'say', lambda level, text: said.append((level, text)))
    instances = Instances({'local': 'inactive', 'remote': 'inactive'})
    beat = _beat(instances, {}, here={'local'})
    # an operator deactivates both
    beat.heard(dict(instances.answers))
    assert instances.failed == dict.fromkeys(['local', 'remote'], 'is inactive, not active')
    # and cleans one up: failed still, the state it is in told
    beat.heard({'local': 'unconfigured', 'remote': 'inactive'}, failed={'local', 'remote'})
    assert instances.failed == {'local': 'is unconfigured, not active',
                                'remote': 'is inactive, not active'}
    # then activates both again: failed instances are asked too, here or elsewhere
    beat.heard({'local': 'active', 'remote': 'active'}, failed={'local', 'remote'})
    assert instances.failed == {} and instances.restarted == []
    assert ('info', 'instance local is active again (heartbeat)') in said
    assert ('info', 'instance remote is active again (heartbeat)') in said


def test_failed_instances_are_asked_too(monkeypatch):
    monkeypatch.setattr(drift, 'say', lambda level, text: None)
    instances = Instances({'local': 'active', 'fine': 'active'},
                          failed={'local': 'is inactive, not active'})
    stopping = threading.Event()
    beating = threading.Thread(target=_beat(instances, {}, here={'local', 'fine'}).run,
                               args=(stopping,))
    beating.start()
    try:
        assert wait_until(lambda: not instances.failed)
    finally:
        stopping.set()
        beating.join(5)
    assert 'local' in {name for name, _ in instances.asked}


class Switched(Instances):
    """An instance activated by the manager (a mode's switch) while the heartbeat asked it."""

    def __init__(self) -> None:
        super().__init__({'wrist': 'inactive'})
        self.believed = 'inactive'

    def states(self):
        return {'wrist': self.believed}

    def probe(self, name, timeout):
        answer = super().probe(name, timeout)
        # the switch took it through activate meanwhile: from now on it answers so
        self.believed = self.answers[name] = 'active'
        return answer


def test_an_answer_older_than_a_transition_the_manager_made_meanwhile_says_nothing(
        monkeypatch):
    said = []
    monkeypatch.setattr(heartbeat, 'say', lambda level, text: said.append((level, text)))
    monkeypatch.setattr(drift, 'say', lambda level, text: said.append((level, text)))
    instances = Switched()
    stopping = threading.Event()
    beating = threading.Thread(target=_beat(instances, {}).run, args=(stopping,))
    beating.start()
    assert wait_until(lambda: len(instances.asked) >= 2)
    stopping.set()
    beating.join(5)
    # the first beat's answer, 'inactive', came from before the activation
    assert 'wrist' not in instances.failed, said
    assert not [s for s in said if s[0] == 'error'], said
