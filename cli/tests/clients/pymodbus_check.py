"""An independent Modbus client against gutta-sim: pymodbus over Modbus TCP and RTU over
TCP reads and writes I, Q, AI, AQ and M per the CPU-EC20 mapping (IN1001), and raw
function 13 frames built by hand from UM4001 go over both framings.

Usage: pymodbus_check.py TCP_PORT RTU_TCP_PORT. Exit status 0 when every check holds;
each failed check is printed.
"""

import socket
import struct
import sys

from pymodbus.client import ModbusTcpClient
from pymodbus.framer import Framer

FAILURES = []


def check(name, got, want):
    if got != want:
        FAILURES.append(f"{name}: got {got!r}, want {want!r}")


def crc16(data):
    crc = 0xFFFF
    for byte in data:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc


def modbus_checks(client, label):
    # M: MW24 and MW26 are 400021 and 400022 (wire 20, 21); the pointer example set them.
    rr = client.read_holding_registers(20, 2, slave=1)
    check(f"{label} MW24/MW26", rr.registers, [0x0E01, 0x0E02])
    # AQ: AQW0 = 400001 (wire 0): write then read back.
    client.write_register(0, 1234, slave=1)
    check(f"{label} AQW0", client.read_holding_registers(0, 1, slave=1).registers, [1234])
    client.write_registers(2, [7, 8], slave=1)
    check(f"{label} AQW4/AQW6", client.read_holding_registers(2, 2, slave=1).registers, [7, 8])
    # Q: Q3.0 is coil 000025 (wire 24).
    client.write_coil(24, True, slave=1)
    check(f"{label} Q3.0", client.read_coils(24, 1, slave=1).bits[0], True)
    client.write_coils(40, [True, False, True], slave=1)
    check(f"{label} Q5.0..Q5.2", client.read_coils(40, 3, slave=1).bits[:3], [True, False, True])
    # I and AI are read-only tables here (all zero: nothing drives the inputs).
    check(f"{label} I0.0..I0.7", client.read_discrete_inputs(0, 8, slave=1).bits[:8], [False] * 8)
    check(f"{label} AIW0", client.read_input_registers(0, 1, slave=1).registers, [0])
    # Past the end of the holding registers (J ends at 400112): exception 02.
    rr = client.read_holding_registers(111, 2, slave=1)
    check(f"{label} past J is an exception", rr.isError(), True)
    check(f"{label} exception code", getattr(rr, "exception_code", None), 2)
    # A bad quantity: exception 03.
    rr = client.read_holding_registers(0, 126, slave=1)
    check(f"{label} 126 registers", getattr(rr, "exception_code", None), 3)


def gutta_tcp(port):
    """GET_PLC_NAME without login fails (81 20), ATTACH with the factory password
    succeeds, then GET_PLC_NAME answers CPU-EC20."""
    s = socket.create_connection(("127.0.0.1", port), timeout=5)

    def ask(tid, gutta):
        pdu = bytes([0x0D]) + gutta
        s.sendall(struct.pack(">HHHB", tid, 0, len(pdu) + 1, 1) + pdu)
        head = s.recv(7)
        length = struct.unpack(">H", head[4:6])[0]
        return s.recv(length - 1)

    check("TCP GET_PLC_NAME before ATTACH", ask(1, bytes.fromhex("0004 0120 8000")), bytes.fromhex("0d 0004 8120 8000"))
    check("TCP ATTACH", ask(2, bytes.fromhex("0014 0110 8000") + b"\xff" * 16), bytes.fromhex("0d 0004 0110 8000"))
    name = ask(3, bytes.fromhex("0004 0120 8000"))
    check("TCP GET_PLC_NAME", name[:7], bytes.fromhex("0d 0014 0120 8000"))
    check("TCP PLC name", name[7:].rstrip(b"\0"), b"CPU-EC20")
    check("TCP DETACH", ask(4, bytes.fromhex("0004 0111 8000")), bytes.fromhex("0d 0004 0111 8000"))
    s.close()


def gutta_rtu(port):
    """STATUS_READ without login fails; a frame with a bad CRC gets no answer, and the
    next good frame is answered."""
    s = socket.create_connection(("127.0.0.1", port), timeout=5)
    frame = bytes([1, 0x0D]) + bytes.fromhex("0004 0A00 8000")
    bad = frame + struct.pack("<H", crc16(frame) ^ 0xFFFF)
    good = frame + struct.pack("<H", crc16(frame))
    s.sendall(bad + good)
    answer = s.recv(64)
    want = bytes([1, 0x0D]) + bytes.fromhex("0004 8A00 8000")
    check("RTU answer after a bad CRC", answer, want + struct.pack("<H", crc16(want)))
    # Broadcast (station 0) is answered for function 13, with the PLC's station.
    frame = bytes([0, 0x0D]) + bytes.fromhex("0004 0A00 8000")
    s.sendall(frame + struct.pack("<H", crc16(frame)))
    check("RTU broadcast answered", s.recv(64)[:2], bytes([1, 0x0D]))
    s.close()


def main():
    tcp_port, rtu_port = int(sys.argv[1]), int(sys.argv[2])
    tcp = ModbusTcpClient("127.0.0.1", port=tcp_port, timeout=5)
    check("TCP connect", tcp.connect(), True)
    modbus_checks(tcp, "TCP")
    tcp.close()
    rtu = ModbusTcpClient("127.0.0.1", port=rtu_port, framer=Framer.RTU, timeout=5)
    check("RTU-over-TCP connect", rtu.connect(), True)
    modbus_checks(rtu, "RTU")
    rtu.close()
    gutta_tcp(tcp_port)
    gutta_rtu(rtu_port)
    for f in FAILURES:
        print("FAIL", f)
    print(f"pymodbus_check: {len(FAILURES)} failures")
    sys.exit(1 if FAILURES else 0)


if __name__ == "__main__":
    main()
