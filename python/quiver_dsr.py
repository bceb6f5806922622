"""quiver.dsr: pydsr's names over Quiver, so that a pydsr agent's graph code runs with its import changed.

    from quiver.dsr import DSRGraph, Node, Edge, Attribute, signals   # was: from pydsr import *

DSRGraph(root, name, id, dsr_input_file="") starts a quiver.Agent named `name` over Cyclone DDS
(loopback by default) and waits briefly for its peers; every method runs on the agent's thread
and returns when done. Node and Edge are plain copies, as in pydsr: change one, then
update_node() / insert_or_assign_edge() writes it back. Ids are integers derived from Quiver's
node ids (the same in every process). Signal callbacks run on the agent's thread.

The differences from pydsr are listed in docs/dsr-api.md ("pydsr users: quiver.dsr").
This source is embedded in the `quiver` module; `_q` is that module.
"""

import hashlib as _hashlib
import math as _math
import struct as _struct
import time as _time

import numpy as _np

__all__ = ["DSRGraph", "Node", "Edge", "Attribute", "signals", "rt_api"]

# RT edges as DSR writes them: translation in millimetres, rotation as Euler angles (rx, ry, rz)
# with R = Rx(rx) Ry(ry) Rz(rz), the convention the importers use (docs/interop.md).
_MM = 1000.0


def _euler_matrix(t_mm, rot):
    rx, ry, rz = (float(a) for a in rot)
    cx, sx, cy, sy, cz, sz = _math.cos(rx), _math.sin(rx), _math.cos(ry), _math.sin(ry), _math.cos(rz), _math.sin(rz)
    Rx = _np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    Ry = _np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    Rz = _np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    X = _np.eye(4)
    X[:3, :3] = Rx @ Ry @ Rz
    X[:3, 3] = [float(v) / _MM for v in t_mm]
    return X


def _rt_attrs(X):
    """DSR's rt_translation (mm) and rt_rotation_euler_xyz of a pose matrix."""
    R = X[:3, :3]
    ry = _math.asin(max(-1.0, min(1.0, R[0, 2])))
    rx = _math.atan2(-R[1, 2], R[2, 2])
    rz = _math.atan2(-R[0, 1], R[0, 0])
    return [float(v) * _MM for v in X[:3, 3]], [rx, ry, rz]


_RT_POSE = ("rt_translation", "rt_rotation_euler_xyz")


def _vec3(name, value):
    """A pose attribute's value as three floats (None if absent)."""
    if value is None:
        return None
    if hasattr(value, "tolist"):  # numpy
        value = value.tolist()
    try:
        out = [float(v) for v in value]
    except (TypeError, ValueError):
        out = []
    if len(out) != 3:
        raise ValueError(f"insert_or_assign_edge(): an RT edge's {name} must be 3 numbers, not {value!r}")
    return out


def _rt_pose(X_PC, t_mm, rot):
    """The pose an RT edge's rt_translation (mm) and rt_rotation_euler_xyz ask for: the current
    X_PC (None if the child is not under that parent yet) with the parts whose values differ from
    what get_edge() shows replaced, so an unchanged part keeps its exact value. None if nothing
    changed."""
    t, r = _vec3("rt_translation", t_mm), _vec3("rt_rotation_euler_xyz", rot)
    if X_PC is None:
        X, old_t, old_r, changed = _np.eye(4), None, None, True
    else:
        X = _np.array(X_PC, dtype=float)
        (old_t, old_r), changed = _rt_attrs(X), False
    if r is not None and r != old_r:
        X[:3, :3] = _euler_matrix([0.0, 0.0, 0.0], r)[:3, :3]
        changed = True
    if t is not None and t != old_t:
        X[:3, 3] = [v / _MM for v in t]
        changed = True
    return X if changed else None


def _int_id(nid):
    """A node's pydsr id: 63 bits of a hash of its Quiver id, the same in every process."""
    r = nid.replica
    h = _hashlib.blake2b(_struct.pack("<QQQ", r.agent, r.incarnation, nid.counter), digest_size=8)
    return int.from_bytes(h.digest(), "little") & ((1 << 63) - 1)


class Attribute:
    """A value with the agent that wrote it (pydsr's Attribute(value[, timestamp], agent_id))."""

    def __init__(self, value, timestamp_or_agent=None, agent_id=None):
        self._value = value
        if agent_id is None:
            self._timestamp = _time.time_ns()
            self._agent_id = timestamp_or_agent or 0
        else:
            self._timestamp = timestamp_or_agent
            self._agent_id = agent_id

    @property
    def value(self):
        return self._value

    @value.setter
    def value(self, v):
        self._value = v
        self._timestamp = _time.time_ns()

    @property
    def agent_id(self):
        return self._agent_id

    @property
    def timestamp(self):
        return self._timestamp

    def __repr__(self):
        return f"<Attribute {self._value!r}>"


class Edge:
    """An edge (pydsr's Edge(to, from, type, agent_id): note the order)."""

    def __init__(self, to, frm, type, agent_id=0):
        self._to, self._from, self._type = to, frm, type
        self.agent_id = agent_id
        self.attrs = {}

    @property
    def origin(self):
        return self._from

    @property
    def destination(self):
        return self._to

    @property
    def type(self):
        return self._type

    def __repr__(self):
        return f"<Edge {self._from} -[{self._type}]-> {self._to}>"


class Node:
    """A node (pydsr's Node(agent_id, type, name="")); id and name are set by insert_node()."""

    def __init__(self, agent_id, type, name=""):
        self._id = None
        self._type = type
        self._name = name
        self.agent_id = agent_id
        self.attrs = {}
        self.edges = {}

    @property
    def id(self):
        return self._id

    @property
    def name(self):
        return self._name

    @property
    def type(self):
        return self._type

    def get_edges(self):
        return list(self.edges.values())

    def __repr__(self):
        return f"<Node {self._id} {self._type} {self._name!r}>"


def _typed(value, current):
    """A Python value as a quiver value: of the attribute's current type where it has one (as
    DSR keeps a type), else int -> int32 (DSR's int) or int64 if it does not fit, float -> float
    (DSR's float), str, bool, bytes or a numpy uint8 array (of any shape: its bytes, row-major), a
    list or array of floats -> float_vec."""
    if isinstance(value, _q.Value):
        return value
    if getattr(value, "dtype", None) == _np.uint8:  # pydsr keeps a uint8 array of any shape as its bytes
        return _q.Value("bytes", value.tobytes())
    if hasattr(value, "tolist"):  # numpy
        value = value.tolist()
    if current is not None and current.type not in ("string", "bool") and not isinstance(value, (str, bool)):
        return _q.Value(current.type, value)
    if isinstance(value, bool) or isinstance(value, str):
        return value
    if isinstance(value, int):
        return _q.Value("int32" if -(1 << 31) <= value < (1 << 31) else "int64", value)
    if isinstance(value, float):
        return _q.Value("float", value)
    if isinstance(value, (bytes, bytearray)):
        return _q.Value("bytes", bytes(value))
    if isinstance(value, (list, tuple)):
        return _q.Value("float_vec", [float(x) for x in value])
    return value


def _same(a, b):
    if hasattr(a, "tolist"):
        a = a.tolist()
    if hasattr(b, "tolist"):
        b = b.tolist()
    return type(a) is type(b) and a == b


def _plain(value):
    return value.value if isinstance(value, Attribute) else value


class _Signals:
    """pydsr's signals: signals.connect(g, signals.UPDATE_NODE, fn)."""

    UPDATE_NODE = 0          # fn(id: int, type: str): a node created or changed
    UPDATE_NODE_ATTR = 1     # fn(id: int, attribute_names: [str])
    UPDATE_EDGE = 2          # fn(from: int, to: int, type: str)
    UPDATE_EDGE_ATTR = 3     # fn(from: int, to: int, type: str, attribute_names: [str])
    DELETE_EDGE = 4          # fn(from: int, to: int, type: str)
    DELETE_NODE = 5          # fn(id: int)
    DELETE_NODE_OBJ = 6      # fn(node: Node): the node as it was
    DELETE_EDGE_OBJ = 7      # fn(edge: Edge): the edge as it was

    @staticmethod
    def connect(g, signal, fn):
        g._connect(signal, fn)


signals = _Signals()


class DSRGraph:
    """pydsr's DSRGraph(root, name, id, dsr_input_file="", all_same_host=True) over a quiver.Agent."""

    def __init__(self, root, name, id, dsr_input_file="", all_same_host=True, *, domain=0,
                 dds_config="loopback", schema=None, join_wait=1.5):
        world_text = _q.convert_world(dsr_input_file) if dsr_input_file else None
        self._agent_id = id
        self._name = name
        self._agent = _q.Agent(name, domain=domain, dds_config=dds_config, world_text=world_text, schema=schema)
        self._ids = {}  # pydsr id -> quiver NodeId
        self._slots = {}  # signal -> [callbacks]
        self._sub = None
        self._created = 0
        deadline = _time.monotonic() + join_wait
        while _time.monotonic() < deadline and self._agent.live_peer_count() == 0:
            _time.sleep(0.02)
        if self._agent.live_peer_count() > 0:
            self._agent.wait_until(lambda g: self._agent.synced(), timeout=max(0.0, deadline - _time.monotonic()) + 1.0)

    # ---- the agent ----
    @property
    def agent(self):
        """The quiver.Agent underneath (its graph, locks, frames)."""
        return self._agent

    def get_agent_id(self):
        return self._agent_id

    def get_agent_name(self):
        return self._name

    def close(self):
        self._agent.stop()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    # ---- ids ----
    def _id(self, nid):
        i = _int_id(nid)
        self._ids[i] = nid
        return i

    def _nid(self, g, ref):
        """The quiver NodeId of a pydsr id or name, or None."""
        if isinstance(ref, str):
            return g.find_node(ref)
        nid = self._ids.get(ref)
        if nid is not None and g.has_node(nid):
            return nid
        for n in g.nodes():  # an id this facade has not seen yet
            if self._id(n) == ref:
                return n
        return None

    # ---- building copies ----
    def _node(self, g, nid):
        n = Node(self._agent_id, g.type_of(nid), g.name_of(nid))
        n._id = self._id(nid)
        for k, v in g.attrs(nid).items():
            if not k.startswith("__") and not k.startswith("rt:"):
                n.attrs[k] = Attribute(v, 0, self._agent_id)
        for key in g.edges_from(nid):
            e = self._edge(g, key)
            n.edges[(e.destination, e.type)] = e
        return n

    def _edge(self, g, key):
        e = Edge(self._id(key.target), self._id(key.source), key.type, self._agent_id)
        for k, v in g.edge_attrs(key).items():
            e.attrs[k] = Attribute(v, 0, self._agent_id)
        if key.type == "RT":
            rt = g.rt_edge(key.target)
            if rt is not None:
                t, r = _rt_attrs(rt[1])
                e.attrs["rt_translation"] = Attribute(t, 0, self._agent_id)
                e.attrs["rt_rotation_euler_xyz"] = Attribute(r, 0, self._agent_id)
        return e

    def _call(self, fn):
        return self._agent.call(fn)

    # ---- nodes ----
    def get_node(self, ref):
        def read(g):
            nid = self._nid(g, ref)
            return None if nid is None else self._node(g, nid)
        return self._call(read)

    def get_node_root(self):
        return self.get_node("root")

    def get_nodes(self):
        return self._call(lambda g: [self._node(g, n) for n in g.nodes()])

    def get_nodes_by_type(self, type):
        return self._call(lambda g: [self._node(g, n) for n in g.nodes(type)])

    def get_name_from_id(self, id):
        def read(g):
            nid = self._nid(g, id)
            return None if nid is None else g.name_of(nid)
        return self._call(read)

    def get_id_from_name(self, name):
        def read(g):
            nid = g.find_node(name)
            return None if nid is None else self._id(nid)
        return self._call(read)

    def size(self):
        return self._call(lambda g: g.node_count)

    def insert_node(self, node):
        """The new node's id, or None if its name is taken (as pydsr)."""
        def write(g):
            if node.name and g.find_node(node.name) is not None:
                return None
            name = node.name
            if not name:
                self._created += 1
                name = f"{node.type}_{self._agent_id}_{self._created}"
            with g.transaction() as tx:
                nid = tx.create_node(node.type, name, {k: _typed(_plain(a), None) for k, a in node.attrs.items()})
            node._id, node._name = self._id(nid), name
            return node._id
        return self._call(write)

    def update_node(self, node):
        """Writes node's attributes back (those it no longer has are removed); False if it is gone."""
        def write(g):
            nid = self._nid(g, node.id if node.id is not None else node.name)
            if nid is None:
                return False
            with g.transaction() as tx:
                for k, a in node.attrs.items():
                    v = _plain(a)
                    current = g.value(nid, k)
                    if current is not None and _same(current.value, v):
                        continue
                    tx.set(nid, k, _typed(v, current))
                for k in g.attrs(nid):
                    if k not in node.attrs and not k.startswith("__") and not k.startswith("rt:"):
                        tx.remove_attr(nid, k)
            return True
        return self._call(write)

    def delete_node(self, ref):
        def write(g):
            nid = self._nid(g, ref)
            if nid is None:
                return False
            with g.transaction() as tx:
                tx.delete_node(nid)
            return True
        return self._call(write)

    # ---- edges ----
    def get_edge(self, frm, to, type):
        def read(g):
            a, b = self._nid(g, frm), self._nid(g, to)
            if a is None or b is None or not g.has_edge(a, b, type):
                return None
            return self._edge(g, _q.EdgeKey(a, b, type))
        return self._call(read)

    def insert_or_assign_edge(self, edge):
        """Inserts the edge, or replaces its attributes; False if an end is missing. An RT edge's
        rt_translation (mm) and rt_rotation_euler_xyz place the child (set_rt: a pose update, or a
        move if the child had another parent); its other attributes replace the RT edge's."""
        def write(g):
            a, b = self._nid(g, edge.origin), self._nid(g, edge.destination)
            if a is None or b is None:
                return False
            if edge.type == "RT":
                self._write_rt(g, a, b, edge.attrs)
                return True
            # DSR's way to replace an edge's attributes: the edge is inserted again with them.
            attrs = {k: _typed(_plain(at), None) for k, at in edge.attrs.items()}
            with g.transaction() as tx:
                tx.insert_edge(a, b, edge.type, attrs)
            return True
        return self._call(write)

    def _write_rt(self, g, parent, child, attrs):
        # DSR keeps an RT edge's pose in two attributes; Quiver keeps it as the edge's pose.
        current = g.rt_edge(child)
        X = _rt_pose(current[1] if current is not None and current[0] == parent else None,
                     _plain(attrs.get("rt_translation")), _plain(attrs.get("rt_rotation_euler_xyz")))
        rest = {k: _typed(_plain(at), g.value(child, "rt:" + k)) for k, at in attrs.items() if k not in _RT_POSE}
        with g.transaction() as tx:
            if X is not None:
                tx.set_rt(parent, child, X, stamp=_time.monotonic_ns())
            tx.insert_edge(parent, child, "RT", rest)  # replaces the RT edge's attributes

    def delete_edge(self, frm, to, type):
        def write(g):
            a, b = self._nid(g, frm), self._nid(g, to)
            if a is None or b is None or not g.has_edge(a, b, type):
                return False
            with g.transaction() as tx:
                tx.delete_edge(a, b, type)
            return True
        return self._call(write)

    def get_edges_by_type(self, type):
        return self._call(lambda g: [self._edge(g, k) for k in g.edges(type)])

    def get_edges_to_id(self, id):
        def read(g):
            nid = self._nid(g, id)
            return [] if nid is None else [self._edge(g, k) for k in g.edges_to(nid)]
        return self._call(read)

    def get_edges(self, id):
        def read(g):
            nid = self._nid(g, id)
            return [] if nid is None else [self._edge(g, k) for k in g.edges_from(nid)]
        return self._call(read)

    # ---- signals ----
    def _connect(self, signal, fn):
        if signal not in range(8):
            raise ValueError(f"signals.connect(): unknown signal {signal!r} (UPDATE_NODE ... DELETE_EDGE_OBJ)")
        self._slots.setdefault(signal, []).append(fn)
        if self._sub is None:
            self._sub = self._agent.subscribe(self._dispatch)

    def _emit(self, signal, *args):
        for fn in self._slots.get(signal, ()):
            fn(*args)

    def _dispatch(self, batch):
        g = self._agent.graph
        for c in batch.nodes:
            i = self._id(c.id)
            if c.kind == "deleted":
                self._emit(signals.DELETE_NODE, i)
                if signals.DELETE_NODE_OBJ in self._slots:
                    n = Node(self._agent_id, c.type, c.name)
                    n._id = i
                    n.attrs = {k: Attribute(v, 0, self._agent_id) for k, v in c.values.items()}
                    self._emit(signals.DELETE_NODE_OBJ, n)
            elif c.kind == "created":
                self._emit(signals.UPDATE_NODE, i, c.type)
            else:
                attrs = [a for a in c.attrs if not a.startswith("__")]
                if attrs:
                    self._emit(signals.UPDATE_NODE_ATTR, i, attrs)
                if attrs or c.renamed:  # DSR signals a node's update with its attributes' too
                    self._emit(signals.UPDATE_NODE, i, c.type)
        for c in batch.edges:
            fr, to, t = self._id(c.key.source), self._id(c.key.target), c.key.type
            if c.kind == "deleted":
                self._emit(signals.DELETE_EDGE, fr, to, t)
                if signals.DELETE_EDGE_OBJ in self._slots:
                    e = Edge(to, fr, t, self._agent_id)
                    e.attrs = {k: Attribute(v, 0, self._agent_id) for k, v in c.values.items()}
                    self._emit(signals.DELETE_EDGE_OBJ, e)
            elif c.kind == "created":
                self._emit(signals.UPDATE_EDGE, fr, to, t)
            elif c.attrs:
                self._emit(signals.UPDATE_EDGE_ATTR, fr, to, t, list(c.attrs))
                self._emit(signals.UPDATE_EDGE, fr, to, t)


class rt_api:
    """pydsr's rt_api(g): RT edges as translation (mm) and Euler XYZ angles."""

    def __init__(self, g):
        self._g = g

    def insert_or_assign_edge_RT(self, node, to, translation, rotation_euler):
        """Places node `to` (an id) under `node` (a Node, its parent) at that pose."""
        g = self._g

        def write(graph):
            parent, child = g._nid(graph, node.id), g._nid(graph, to)
            if parent is None or child is None:
                return False
            with graph.transaction() as tx:
                tx.set_rt(parent, child, _euler_matrix(translation, rotation_euler), stamp=_time.monotonic_ns())
            return True
        return g._call(write)

    def get_edge_RT(self, node, to):
        """The RT edge from `node` (a Node) to node `to` (an id), with rt_translation and
        rt_rotation_euler_xyz; None if `to` is not `node`'s child."""
        g = self._g

        def read(graph):
            parent, child = g._nid(graph, node.id), g._nid(graph, to)
            if parent is None or child is None or graph.rt_parent(child) != parent:
                return None
            return g._edge(graph, _q.EdgeKey(parent, child, "RT"))
        return g._call(read)

    def get_translation(self, node_id, to):
        """rt_translation (mm) of the RT edge node_id -> to, or None."""
        node = self._g.get_node(node_id)
        e = None if node is None else self.get_edge_RT(node, to)
        return None if e is None else e.attrs["rt_translation"].value
