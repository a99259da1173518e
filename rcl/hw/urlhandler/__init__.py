"""pyserial URL handlers of rcl (found by module name: protocol_<scheme>)."""
