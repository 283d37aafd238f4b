"""A small, generic PLY reader on numpy (ascii, binary little- and big-endian).

The header is read generically: any elements, scalar properties of every PLY type (both the
classic "uchar" and the sized "uint8" spellings) and list properties. `read(path)` returns a dict
element name -> Element, in file order. Scalar properties are 1-D numpy arrays; list properties
are a 2-D array when every item has the same length (a triangle mesh's vertex_indices) and a list
of 1-D arrays otherwise. Errors raise common.InputError naming the file, the header line or the
element item, and what was expected.
"""


import numpy as np

from common import InputError, require_file, write_atomically

TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}
FORMATS = {"ascii": None, "binary_little_endian": "<", "binary_big_endian": ">"}


class Property:
    def __init__(self, name, dtype, count_dtype=None):
        self.name = name
        self.dtype = dtype              # numpy type code of the values ("f4", "u1", ...)
        self.count_dtype = count_dtype  # list properties: type code of the per-item count

    @property
    def is_list(self):
        return self.count_dtype is not None


class Element:
    def __init__(self, name, count):
        self.name = name
        self.count = count
        self.properties = []  # Property, in file order
        self.data = {}        # property name -> numpy array (or list of arrays, see module doc)

    def __getitem__(self, name):
        return self.data[name]

    def __contains__(self, name):
        return name in self.data


def _header(path, handle):
    """Parses the header; returns (format name, [Element], comments)."""
    def line_of(number):
        raw = handle.readline()
        if not raw:
            raise InputError(path, f"line {number}", "unexpected end of file in the header (no end_header)")
        try:
            return raw.decode("ascii").rstrip("\r\n")
        except UnicodeDecodeError:
            raise InputError(path, f"line {number}", "expected an ASCII header line") from None

    if line_of(1).strip() != "ply":
        raise InputError(path, "line 1", "expected the magic line \"ply\"")
    fmt = None
    elements = []
    comments = []
    number = 1
    while True:
        number += 1
        words = line_of(number).split()
        if not words:
            continue
        keyword = words[0]
        if keyword == "end_header":
            break
        if keyword in ("comment", "obj_info"):
            comments.append(" ".join(words[1:]))
        elif keyword == "format":
            if len(words) != 3 or words[1] not in FORMATS:
                raise InputError(path, f"line {number}",
                                 "expected \"format ascii|binary_little_endian|binary_big_endian 1.0\"")
            fmt = words[1]
        elif keyword == "element":
            if len(words) != 3 or not words[2].isdigit():
                raise InputError(path, f"line {number}", "expected \"element NAME COUNT\"")
            elements.append(Element(words[1], int(words[2])))
        elif keyword == "property":
            if not elements:
                raise InputError(path, f"line {number}", "property before any element")
            if len(words) == 5 and words[1] == "list":
                if words[2] not in TYPES or words[3] not in TYPES or TYPES[words[2]][0] == "f":
                    raise InputError(path, f"line {number}",
                                     "expected \"property list COUNT_TYPE ITEM_TYPE NAME\" with an integer count type")
                elements[-1].properties.append(Property(words[4], TYPES[words[3]], TYPES[words[2]]))
            elif len(words) == 3 and words[1] in TYPES:
                elements[-1].properties.append(Property(words[2], TYPES[words[1]]))
            else:
                raise InputError(path, f"line {number}", "expected \"property TYPE NAME\" with a PLY type")
        else:
            raise InputError(path, f"line {number}", f"unknown header keyword \"{keyword}\"")
    if fmt is None:
        raise InputError(path, "header", "no format line")
    return fmt, elements, comments


def _read_binary_element(path, element, buffer, offset, order):
    """Reads one element's items from `buffer` at `offset`; returns the offset after them."""
    def truncated(item):
        return InputError(path, f"{element.name} {item}", "truncated data (file ends inside this element)")

    if element.count == 0:
        for prop in element.properties:
            element.data[prop.name] = np.zeros((0, 0) if prop.is_list else 0, dtype=prop.dtype)
        return offset
    # Fast path: guess every list's length from the first item and read all items at once.
    lengths = {}
    position = offset
    for prop in element.properties:
        if prop.is_list:
            size = np.dtype(prop.count_dtype).itemsize
            if position + size > len(buffer):
                raise truncated(0)
            lengths[prop.name] = max(0, int(np.frombuffer(buffer, order + prop.count_dtype, 1, position)[0]))
            position += size + lengths[prop.name] * np.dtype(prop.dtype).itemsize
        else:
            position += np.dtype(prop.dtype).itemsize
    fields = []
    for prop in element.properties:
        if prop.is_list:
            fields.append(("count_" + prop.name, order + prop.count_dtype))
            fields.append(("list_" + prop.name, order + prop.dtype, (lengths[prop.name],)))
        else:
            fields.append(("scalar_" + prop.name, order + prop.dtype))
    record = np.dtype(fields)
    end = offset + record.itemsize * element.count
    if end <= len(buffer):
        items = np.frombuffer(buffer, record, element.count, offset)
        if all(np.all(items["count_" + name] == length) for name, length in lengths.items()):
            for prop in element.properties:
                key = ("list_" if prop.is_list else "scalar_") + prop.name
                element.data[prop.name] = items[key].astype(items[key].dtype.newbyteorder("="))
            return end
    # General path: lists of varying length, item by item.
    values = {prop.name: [] for prop in element.properties}
    for item in range(element.count):
        for prop in element.properties:
            if prop.is_list:
                size = np.dtype(prop.count_dtype).itemsize
                if offset + size > len(buffer):
                    raise truncated(item)
                length = int(np.frombuffer(buffer, order + prop.count_dtype, 1, offset)[0])
                if length < 0:
                    raise InputError(path, f"{element.name} {item}", f"negative list length of {prop.name}")
                offset += size
                size = length * np.dtype(prop.dtype).itemsize
                if offset + size > len(buffer):
                    raise truncated(item)
                values[prop.name].append(np.frombuffer(buffer, order + prop.dtype, length, offset).astype(prop.dtype))
                offset += size
            else:
                size = np.dtype(prop.dtype).itemsize
                if offset + size > len(buffer):
                    raise truncated(item)
                values[prop.name].append(np.frombuffer(buffer, order + prop.dtype, 1, offset)[0])
                offset += size
    for prop in element.properties:
        element.data[prop.name] = (_lists(values[prop.name], prop.dtype) if prop.is_list
                                   else np.array(values[prop.name], dtype=prop.dtype))
    return offset


def _lists(arrays, dtype):
    if arrays and all(len(array) == len(arrays[0]) for array in arrays):
        return np.array(arrays, dtype=dtype)
    if not arrays:
        return np.zeros((0, 0), dtype=dtype)
    return arrays


def _read_ascii(path, elements, text):
    tokens = text.split()
    position = 0

    def take(element, item, prop, dtype):
        nonlocal position
        if position >= len(tokens):
            raise InputError(path, f"{element.name} {item}", "truncated data (file ends inside this element)")
        token = tokens[position]
        position += 1
        try:
            return float(token) if dtype[0] == "f" else int(token)
        except ValueError:
            raise InputError(path, f"{element.name} {item}, property {prop.name}",
                             f"expected a number, found \"{token.decode(errors='replace')}\"") from None

    for element in elements:
        values = {prop.name: [] for prop in element.properties}
        for item in range(element.count):
            for prop in element.properties:
                if prop.is_list:
                    length = take(element, item, prop, prop.count_dtype)
                    if length < 0:
                        raise InputError(path, f"{element.name} {item}", f"negative list length of {prop.name}")
                    values[prop.name].append(np.array([take(element, item, prop, prop.dtype) for _ in range(length)],
                                                      dtype=prop.dtype))
                else:
                    values[prop.name].append(take(element, item, prop, prop.dtype))
        for prop in element.properties:
            element.data[prop.name] = (_lists(values[prop.name], prop.dtype) if prop.is_list
                                       else np.array(values[prop.name], dtype=prop.dtype))


def read(path):
    """Reads a PLY file; returns {element name: Element}. Raises InputError."""
    require_file(path)
    with open(path, "rb") as handle:
        fmt, elements, _ = _header(path, handle)
        body = handle.read()
    names = [element.name for element in elements]
    if len(set(names)) != len(names):
        raise InputError(path, "header", "an element name appears twice")
    order = FORMATS[fmt]
    if order is None:
        _read_ascii(path, elements, body)
    else:
        offset = 0
        for element in elements:
            offset = _read_binary_element(path, element, body, offset, order)
    return {element.name: element for element in elements}


def comments(path):
    """The header's comment lines of a PLY file (without the keyword), in order. Raises InputError."""
    require_file(path)
    with open(path, "rb") as handle:
        return _header(path, handle)[2]


def write_binary(path, elements, comments=()):
    """Writes a binary little-endian PLY (for tests and fixtures), atomically.

    `elements`: [(name, [(property name, type name, values)])]; a list property is given as
    ("vertex_indices", "list uchar uint", 2-D array). `comments`: header comment lines.
    """
    header = ["ply", "format binary_little_endian 1.0"] + [f"comment {text}" for text in comments]
    blocks = []
    for name, props in elements:
        count = len(props[0][2]) if props else 0
        header.append(f"element {name} {count}")
        fields = []
        for prop_name, type_name, values in props:
            header.append(f"property {type_name} {prop_name}")
            words = type_name.split()
            if words[0] == "list":
                array = np.asarray(values)
                fields.append((f"n_{prop_name}", "<" + TYPES[words[1]]))
                fields.append((prop_name, "<" + TYPES[words[2]], (array.shape[1],)))
            else:
                fields.append((prop_name, "<" + TYPES[type_name]))
        record = np.zeros(count, dtype=np.dtype(fields))
        for prop_name, type_name, values in props:
            if type_name.startswith("list"):
                record[f"n_{prop_name}"] = np.asarray(values).shape[1]
            record[prop_name] = values
        blocks.append(record.tobytes())
    header.append("end_header")
    # Atomically, mode 0644: a temporary file in the same folder, renamed over `path` once complete.
    def write(stream):
        stream.write(("\n".join(header) + "\n").encode("ascii"))
        for block in blocks:
            stream.write(block)

    write_atomically(path, ".ply", write)


__all__ = ["read", "comments", "write_binary", "Element", "Property", "TYPES"]
