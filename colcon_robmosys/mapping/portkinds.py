# Copyright 2026 The colcon-robmosys authors
# Licensed under the Apache License, Version 2.0

"""The one table of what each port becomes in ROS 2, by pattern and role.

Every layer that needs to know what a port is reads this table: the check
(which ports may trigger an activity, which need one, which signatures
clash), the mapping of components and every language backend's spelling
tables (:mod:`colcon_robmosys.mapping.backends`).
A new communication pattern is one row here.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from colcon_robmosys.model.types import Pattern, Port, Role


class Entity(str, Enum):
    """The ROS 2 entity a port becomes; names a template fragment per language."""

    PUBLISHER = 'publisher'
    SUBSCRIPTION = 'subscription'
    SERVICE = 'service'
    CLIENT = 'client'
    ACTION_SERVER = 'action_server'
    ACTION_CLIENT = 'action_client'
    EVENT_SERVER = 'event_server'
    EVENT_CLIENT = 'event_client'


class Delivery(str, Enum):
    """What a port hands to the functions of the activity it triggers."""

    #: each message received: ``(commobj)``
    MESSAGE = 'message'
    #: each request, to fill in the answer: ``(request, response)``
    REQUEST = 'request'
    #: each answer of an asynchronous query: ``(commobj)``
    ANSWER = 'answer'
    #: each goal, to return its result: ``(goal_handle)``
    GOAL = 'goal'
    #: each result of a goal sent: ``(commobj)``
    RESULT = 'result'
    #: the condition of an activation, tested per event: ``(activation, event)``
    ACTIVATION = 'activation'
    #: each event that fires: ``(commobj)``
    EVENT = 'event'


class Returns(str, Enum):
    """What a function run by a port gives back to it."""

    NOTHING = 'nothing'
    #: the filled-in answer of a query (``response``)
    ANSWER = 'answer'
    #: the result of an action goal
    RESULT = 'result'
    #: whether an event fires for an activation
    CONDITION = 'condition'
    #: why a parameter value is refused (validators, run on a change, not by a port)
    PROBLEM = 'problem'


@dataclass(frozen=True)
class PortKind:
    """What a port of one pattern and role becomes."""

    pattern: Pattern
    role: Role
    entity: Entity
    #: what it hands to the activity it triggers; None: it cannot trigger one
    delivers: Delivery | None
    #: how the check words what it delivers
    delivers_text: str
    #: the arguments of a function it runs, in order
    arguments: tuple[str, ...]
    returns: Returns
    #: a provided port that cannot work unless an activity answers it
    needs_handler: bool = False
    #: its activity has exactly one function: the one that returns
    one_function: bool = False
    #: it reads or writes a DDS topic, so the model's QoS applies
    topic_qos: bool = False
    #: blocking waits for its answers run in a callback group of their own
    own_group: bool = False
    #: it is made of ROS 2 actions (rclcpp_action, rclpy.action)
    uses_actions: bool = False
    #: the runtime class it is an instance of (clients, events), if any
    runtime_class: bool = False
    #: of the two ends of a connection on a topic, this one writes it
    topic_writer: bool = False
    #: the server of a name: a system connects one such port per name
    unique_server: bool = False
    #: the data of its pattern flows to the provided end (diagram arrows)
    data_to_provider: bool = False
    #: its methods that wait for an answer the executor delivers: a function that
    #: calls one needs a thread of the executor to be free meanwhile
    blocking_calls: tuple[str, ...] = ()

    @property
    def triggers(self) -> bool:
        """Tell whether the port may trigger an activity."""
        return self.delivers is not None


_COMMOBJ = ('commobj',)

_ROWS = (
    PortKind(Pattern.PUSH, Role.PROVIDED, Entity.PUBLISHER, None, '', (),
             Returns.NOTHING, topic_qos=True, topic_writer=True),
    PortKind(Pattern.PUSH, Role.REQUIRED, Entity.SUBSCRIPTION, Delivery.MESSAGE,
             'each message received', _COMMOBJ, Returns.NOTHING, topic_qos=True),
    PortKind(Pattern.SEND, Role.REQUIRED, Entity.PUBLISHER, None, '', (),
             Returns.NOTHING, topic_qos=True, topic_writer=True,
             data_to_provider=True),
    PortKind(Pattern.SEND, Role.PROVIDED, Entity.SUBSCRIPTION, Delivery.MESSAGE,
             'each message received', _COMMOBJ, Returns.NOTHING, topic_qos=True,
             data_to_provider=True),
    PortKind(Pattern.QUERY, Role.PROVIDED, Entity.SERVICE, Delivery.REQUEST,
             'each request, returning the answer', ('request', 'response'),
             Returns.ANSWER, needs_handler=True, one_function=True,
             unique_server=True, data_to_provider=True),
    PortKind(Pattern.QUERY, Role.REQUIRED, Entity.CLIENT, Delivery.ANSWER,
             'each answer of an asynchronous call', _COMMOBJ, Returns.NOTHING,
             own_group=True, runtime_class=True, data_to_provider=True,
             blocking_calls=('call',)),
    PortKind(Pattern.ACTION, Role.PROVIDED, Entity.ACTION_SERVER, Delivery.GOAL,
             'each goal, returning the result', ('goal_handle',), Returns.RESULT,
             needs_handler=True, one_function=True, uses_actions=True,
             unique_server=True, data_to_provider=True),
    PortKind(Pattern.ACTION, Role.REQUIRED, Entity.ACTION_CLIENT, Delivery.RESULT,
             'each result of a goal sent', _COMMOBJ, Returns.NOTHING,
             own_group=True, uses_actions=True, runtime_class=True,
             data_to_provider=True, blocking_calls=('send_goal',)),
    PortKind(Pattern.EVENT, Role.PROVIDED, Entity.EVENT_SERVER, Delivery.ACTIVATION,
             'the condition of each activation', ('activation', 'event'),
             Returns.CONDITION, one_function=True, topic_qos=True,
             uses_actions=True, runtime_class=True, topic_writer=True,
             unique_server=True),
    PortKind(Pattern.EVENT, Role.REQUIRED, Entity.EVENT_CLIENT, Delivery.EVENT,
             'each event that fires', _COMMOBJ, Returns.NOTHING, topic_qos=True,
             own_group=True, uses_actions=True, runtime_class=True),
)

#: (pattern, role) -> what such a port becomes
PORT_KINDS: dict[tuple[Pattern, Role], PortKind] = {
    (k.pattern, k.role): k for k in _ROWS}


def port_kind(port: Port) -> PortKind:
    """Return what a port becomes."""
    return PORT_KINDS[(port.pattern, port.role)]
