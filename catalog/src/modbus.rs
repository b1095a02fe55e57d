//! Modbus view of the memory map (filled in below).
