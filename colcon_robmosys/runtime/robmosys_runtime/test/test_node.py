# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0
"""ComponentNode's lifecycle bookkeeping on real rclpy lifecycle nodes."""

import threading

from conftest import answer, wait_until
import rclpy
from rclpy.lifecycle import TransitionCallbackReturn
from rclpy.node import Node
from rclpy.qos import QoSProfile
from robmosys_runtime import ComponentNode
from std_msgs.msg import Int32
from test_msgs.srv import BasicTypes

QOS = QoSProfile(depth=10)


class Counter(ComponentNode):
    """Publishes a count periodically, receives it, and answers a query."""

    def __init__(self, context, fail_configure=False) -> None:
        # the count comes back: sCount is connected to pCount by remapping
        super().__init__('counter', context=context,
                         cli_args=['--ros-args', '-r', 'sCount:=pCount'],
                         ports=('pCount', 'sCount', 'qAdd'),
                         activities=('Tick', 'OnCount', 'Answer'),
                         lifecycle={'on_configure': [self.fSetUp],
                                    'on_cleanup': [self.fTearDown]})
        self.fail_configure = fail_configure
        self.count = 0
        self.received = []
        self.torn_down = False
        self.in_tick = threading.Lock()

    def create_ports(self) -> None:
        self.add_publisher('pCount', Int32, QOS)
        self.add_subscription('sCount', Int32, QOS, 'OnCount', [self.fReceive])
        self.add_service('qAdd', BasicTypes, 'Answer', self.fAnswer)
        self.add_periodic('Tick', 0.05, [self.fTick])

    def fSetUp(self) -> None:
        if self.fail_configure:
            raise RuntimeError('the set-up fails')

    def fTearDown(self) -> None:
        self.torn_down = True

    def fTick(self) -> None:
        self.count += 1
        self.pCount.publish(Int32(data=self.count))
        if self.count == 3:
            raise RuntimeError('the third tick fails')

    def fReceive(self, message) -> None:
        self.received.append(message.data)

    def fAnswer(self, request, response):
        response.int32_value = request.int32_value * 2
        return response


def _lifecycle(node, transition):
    return getattr(node, f'trigger_{transition}')()


def test_ports_live_from_configure_to_cleanup(spinning):
    node = spinning.add(Counter(spinning.context))
    assert node.pCount is None and node.sCount is None and node.qAdd is None
    _lifecycle(node, 'configure')
    assert node.pCount is not None and node.sCount is not None and node.qAdd is not None
    assert node.count == 0  # inactive: the timer does not run
    _lifecycle(node, 'activate')
    assert node.active
    assert wait_until(lambda: len(node.received) >= 5), (node.count, node.received)
    assert node.count >= 5  # a failing tick went on
    _lifecycle(node, 'deactivate')
    assert not node.active
    stopped = node.count
    assert not wait_until(lambda: node.count > stopped + 1, 0.3)
    _lifecycle(node, 'cleanup')
    assert node.torn_down
    assert node.pCount is None and node.sCount is None and node.qAdd is None
    # configured again, every port comes back
    _lifecycle(node, 'configure')
    assert node.pCount is not None


def test_the_node_keeps_rclpy_s_list_of_its_timers(spinning):
    # ComponentNode kept its activities' timers in rclpy's own Node._timers:
    # each was then in the node's timers twice (twice in every wait set), and
    # cleanup dropped the node's other timers from the executor's sight
    node = spinning.add(Counter(spinning.context))
    beats = []
    own = node.create_timer(0.05, lambda: beats.append(1))
    _lifecycle(node, 'configure')
    timers = list(node.timers)
    assert len(timers) == len(set(timers)) == 2 and own in timers
    _lifecycle(node, 'cleanup')
    assert list(node.timers) == [own]
    beats.clear()
    assert wait_until(lambda: len(beats) >= 2)


def test_queries_are_answered_while_active_only(spinning):
    node = spinning.add(Counter(spinning.context))
    client_node = spinning.add(Node('asker', context=spinning.context))
    client = client_node.create_client(BasicTypes, 'qAdd')
    _lifecycle(node, 'configure')
    assert client.wait_for_service(timeout_sec=10)

    def ask(value):
        response = answer(client, BasicTypes.Request(int32_value=value))
        assert response is not None, 'no answer on qAdd in 20 s'
        return response.int32_value
    assert ask(21) == 0  # inactive: the default response
    _lifecycle(node, 'activate')
    assert ask(21) == 42


def test_a_raising_hook_fails_its_transition_and_releases(spinning, capfd):
    node = spinning.add(Counter(spinning.context, fail_configure=True))
    result = node.on_configure(None)
    assert result == TransitionCallbackReturn.FAILURE
    assert node.pCount is None and node.qAdd is None
    err = capfd.readouterr().err
    assert 'configure failed:' in err and 'Traceback' in err and 'the set-up fails' in err


def test_an_activity_failure_is_logged_with_its_traceback(spinning, capfd):
    node = spinning.add(Counter(spinning.context))
    _lifecycle(node, 'configure')
    _lifecycle(node, 'activate')
    assert wait_until(lambda: node.count >= 4)
    err = capfd.readouterr().err
    assert 'activity Tick failed:' in err and 'the third tick fails' in err


def test_every_activity_has_its_own_exclusive_group(spinning):
    node = Counter(spinning.context)
    groups = {name: a.callback_group for name, a in node.activities.items()}
    assert set(groups) == {'Tick', 'OnCount', 'Answer'}
    assert len({id(g) for g in groups.values()}) == 3
    node.destroy_node()


def test_a_transition_requested_after_shutdown_is_refused(capfd):
    # SIGINT or SIGTERM shuts the context down while the executor's threads
    # still run: a change_state request taken then is answered as refused,
    # rather than started (rclpy logged 'Unable to start transition' and left
    # the node in 'activating': seen in one shutdown in five under load)
    from lifecycle_msgs.msg import Transition
    from lifecycle_msgs.srv import ChangeState, GetState
    context = rclpy.Context()
    rclpy.init(context=context)
    node = Counter(context)
    services = {s.srv_name.rsplit('/', 1)[-1]: s for s in node.services}

    def call(name, srv_type, **fields):
        # as rclpy's executor does with a request it took
        return services[name].callback(srv_type.Request(**fields), srv_type.Response())

    configure = Transition(id=Transition.TRANSITION_CONFIGURE)
    activate = Transition(id=Transition.TRANSITION_ACTIVATE)
    assert call('change_state', ChangeState, transition=configure).success
    rclpy.shutdown(context=context)
    assert not call('change_state', ChangeState, transition=activate).success
    assert call('get_state', GetState).current_state.label == 'inactive'
    node.destroy_node()
    assert 'Unable to start transition' not in capfd.readouterr().err
