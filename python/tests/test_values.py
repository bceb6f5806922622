import numpy as np
import pytest
import quiver


def roundtrip(value):
    g = quiver.Graph()
    with g.transaction() as t:
        n = t.create_node("thing", "x")
        t.set(n, "v", value)
    return g.get(n, "v"), g.value(n, "v").type


def test_scalars():
    assert roundtrip(7) == (7, "int64")
    assert roundtrip(-2**63) == (-2**63, "int64")
    assert roundtrip(2**64 - 1) == (2**64 - 1, "uint64")
    assert roundtrip(2.5) == (2.5, "double")
    assert roundtrip(True) == (True, "bool")
    assert roundtrip("héllo") == ("héllo", "string")
    assert roundtrip(b"\x00\xff") == (b"\x00\xff", "bytes")
    assert roundtrip(np.float32(1.5)) == (1.5, "float")
    assert roundtrip(np.int32(-3)) == (-3, "int32")


def test_arrays_become_numpy():
    v, t = roundtrip(np.array([1, 2, 3], dtype=np.float32))
    assert t == "float_vec" and v.dtype == np.float32 and v.tolist() == [1, 2, 3]
    v, t = roundtrip([1.0, 2.0])
    assert t == "double_vec" and v.dtype == np.float64 and v.tolist() == [1, 2]
    v, t = roundtrip(np.array([1, 2**63], dtype=np.uint64))
    assert t == "uint64_vec" and v.tolist() == [1, 2**63]
    m = np.arange(16, dtype=np.float64).reshape(4, 4)
    v, t = roundtrip(m)
    assert t == "mat4d" and v.shape == (4, 4) and np.array_equal(v, m)


def test_typed_values():
    v, t = roundtrip(quiver.Value("vec3f", [1, 2, 3]))
    assert t == "vec3f" and v.dtype == np.float32 and v.tolist() == [1, 2, 3]
    assert roundtrip(quiver.Value("int32", 5)) == (5, "int32")
    assert quiver.Value("vec2f", (1, 2)) == quiver.Value("vec2f", np.array([1, 2]))
    with pytest.raises(ValueError, match="vec3f takes 3 numbers"):
        quiver.Value("vec3f", [1, 2])
    with pytest.raises(ValueError, match="unknown type 'vec5f'"):
        quiver.Value("vec5f", [1])
    with pytest.raises(TypeError, match="str as int32"):
        quiver.Value("int32", "five")


def test_an_existing_attribute_keeps_its_type():
    g = quiver.Graph()
    with g.transaction() as t:
        n = t.create_node("thing", "x", {"count": quiver.Value("int32", 1), "pos": quiver.Value("vec3f", [0, 0, 0]),
                                          "ratio": 1.0})
    with g.transaction() as t:
        t.set(n, "count", 42)
        t.set(n, "pos", [1.0, 2.0, 3.0])
        t.set(n, "ratio", 2)
    assert g.value(n, "count").type == "int32" and g.get(n, "count") == 42
    assert g.value(n, "pos").type == "vec3f" and g.get(n, "pos").tolist() == [1, 2, 3]
    assert g.value(n, "ratio").type == "double" and g.get(n, "ratio") == 2.0
    with pytest.raises(OverflowError, match="does not fit a int32"):
        g.transaction().set(n, "count", 2**40)


def test_type_errors_name_the_types():
    g = quiver.Graph()
    with g.transaction() as t:
        n = t.create_node("thing", "x", {"battery": 0.5})
    with pytest.raises(TypeError, match="dict"):
        g.transaction().set(n, "bad", {"a": 1})
    with pytest.raises(quiver.TypeMismatchError, match="is a double, not a string") as e:
        g.get(n, "battery", type="string")
    assert isinstance(e.value, TypeError) and e.value.code == "type_mismatch"
    assert g.get(n, "battery", type="double") == 0.5
    assert quiver.value_type(np.zeros(3, np.float32)) == "float_vec"
