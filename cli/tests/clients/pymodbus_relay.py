"""An independent Modbus client against `gutta-sim --device relay-board`: pymodbus
switches reporting off as seed document 004 tells (coil 0x1D5C), switches channels with
function 05 on coils 0x0200 + n, reads them back with function 01, sees the board's own
set frame (sent on a raw socket) through Modbus, and gets exceptions for what the board
does not serve.

Usage: pymodbus_relay.py PORT. Exit status 0 when every check holds; each failed check
is printed.
"""

import socket
import sys

from pymodbus.client import ModbusTcpClient

FAILURES = []
FIRST = 0x0200
REPORTING = 0x1D5C


def check(name, got, want):
    if got != want:
        FAILURES.append(f"{name}: got {got!r}, want {want!r}")


def main():
    port = int(sys.argv[1])
    client = ModbusTcpClient("127.0.0.1", port=port, timeout=5)
    check("connect", client.connect(), True)
    check("reporting off", client.write_coil(REPORTING, False, slave=1).isError(), False)
    check("reporting reads off", client.read_coils(REPORTING, 1, slave=1).bits[0], False)
    # Channels 1, 3 and 32 on.
    for n in (1, 3, 32):
        check(f"channel {n} on", client.write_coil(FIRST + n - 1, True, slave=1).isError(), False)
    bits = client.read_coils(FIRST, 32, slave=1).bits
    want = [n in (1, 3, 32) for n in range(1, 33)]
    check("32 channels", bits[:32], want)
    check("channel 3 off", client.write_coil(FIRST + 2, False, slave=1).isError(), False)
    check("channels 1-4", client.read_coils(FIRST, 4, slave=1).bits[:4], [True, False, False, False])
    # The board's own set frame on another connection: channels 1-8 and 17-24 on.
    with socket.create_connection(("127.0.0.1", port), timeout=5) as s:
        s.sendall(bytes.fromhex("03 01 02 00 00 05 00 20 FF 00 FF 00"))
        s.sendall(bytes.fromhex("01 01 02 00 00 05 00 20 00 00 00 00"))
        check("own read", s.recv(12).hex(" "), "01 01 02 01 05 00 00 10 ff 00 ff 00")
    bits = client.read_coils(FIRST, 32, slave=1).bits
    check("after the set frame", bits[:32], [n <= 8 or 17 <= n <= 24 for n in range(1, 33)])
    # Channel 33 does not exist: exception 02. Registers are not served: exception 01.
    rr = client.read_coils(FIRST, 33, slave=1)
    check("33 channels", getattr(rr, "exception_code", None), 2)
    rr = client.write_coil(FIRST + 32, True, slave=1)
    check("channel 33", getattr(rr, "exception_code", None), 2)
    rr = client.read_holding_registers(FIRST, 1, slave=1)
    check("registers", getattr(rr, "exception_code", None), 1)
    client.close()
    for f in FAILURES:
        print("FAIL", f)
    print(f"pymodbus_relay: {len(FAILURES)} failures")
    sys.exit(1 if FAILURES else 0)


if __name__ == "__main__":
    main()
