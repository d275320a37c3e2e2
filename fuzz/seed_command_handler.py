import struct, os, sys
out = sys.argv[1]
def req(tag, op, args=b''):
    rest = bytes([tag, op]) + args
    n = len(rest)
    assert n < 64
    return bytes([(n << 2) | 1]) + rest
def samples(count, codes=(0,0,0,0), err=False, lost=False):
    op = ((count - 1) << 4) | (8 if lost else 0) | (4 if err else 0) | 2
    return bytes([op]) + bytes(codes)
def hw(dac=False, adc=False, stall=False):
    return bytes([3 | (4 if dac else 0) | (8 if adc else 0) | (16 if stall else 0)])
def raw(b):
    return bytes([(len(b) << 2) | 0]) + b
f32 = lambda x: struct.pack('<f', x)
u32 = lambda x: struct.pack('<I', x)
u16 = lambda x: struct.pack('<H', x)
filt = lambda a, o, c: f32(a) + bytes([o]) + f32(c)
cal = b''.join(f32(v) for v in [1,0,0,0,1,0,0,0,1])
seeds = {
 'start_stop': req(1,1) + samples(8) + req(2,2) + samples(4),
 'rate_ok': req(1,3,u32(2000)) + samples(3),
 'rate_bad': req(1,3,u32(1234)),
 'rate_short': req(1,3,b'\x01\x02'),
 'rate_long': req(1,3,u32(1000)+b'\x00'),
 'rate_hw_fail': hw(adc=True) + req(1,3,u32(2000)),
 'filter_ok': req(1,4,filt(0.5,4,50.0)) + req(2,1) + samples(16, (1,2,3,4)),
 'filter_order3': req(1,4,filt(1.0,3,50.0)),
 'filter_alpha0': req(1,4,filt(0.0,2,50.0)),
 'filter_nan': req(1,4,filt(float('nan'),2,50.0)),
 'filter_cutoff_high': req(1,4,filt(1.0,2,600.0)),
 'filter_then_rate': req(1,4,filt(1.0,2,400.0)) + req(2,3,u32(250)),
 'tare_ok': req(1,5,u16(4)) + samples(6,(5,5,5,0)),
 'tare_zero': req(1,5,u16(0)),
 'tare_busy': req(1,5,u16(100)) + samples(1) + req(2,5,u16(3)),
 'clear_tare': req(1,6),
 'autonull': req(1,7) + samples(16,(0x10,0xF0,0,0)) + samples(16),
 'autonull_busy': req(1,7) + samples(1) + req(2,7),
 'autonull_dac_fail': hw(dac=True) + req(1,7),
 'info': req(1,8) + req(2,8),
 'calibration': req(1,9,cal),
 'calibration_inf': req(1,9,cal[:-4]+f32(float('inf'))),
 'calibration_short': req(1,9,cal[:20]),
 'ping': req(1,10,u32(0xDEADBEEF)),
 'ping_short': req(1,10,b'\x01'),
 'drift_on': req(1,11,b'\x01') + samples(16,(1,0xFF,0,0)) + req(2,8),
 'drift_bad_bool': req(1,11,b'\x02'),
 'batch_ok': req(1,12,b'\x01') + req(2,1) + samples(4),
 'batch_zero': req(1,12,b'\x00'),
 'batch_17': req(1,12,bytes([17])),
 'unknown_opcode': req(1,0x7F),
 'no_opcode': req(1,0)[:-1] if False else bytes([(1<<2)|1, 7]),
 'empty_request': bytes([1]),
 'busy_five': b''.join(req(i,1) for i in range(6)),
 'saturate': req(1,1) + samples(4,(0x7F,0x80,0,0x7F)),
 'lost_and_error': req(1,1) + samples(3,err=True) + samples(2,lost=True),
 'stalled_link': req(1,12,bytes([1])) + req(2,1) + hw(stall=True) + samples(16) + samples(16) + b''.join(req(i,10,u32(i)) for i in range(12)) + hw() + samples(4),
 'garbage': raw(b'\x55\x13\x00\x01\x02\x00'),
 'overflow': raw(bytes(range(1,64))) + raw(bytes(range(1,40))+b'\x00'),
 'split_across': raw(b'\x05') + req(3,2),
}
for name, data in seeds.items():
    open(os.path.join(out, name), 'wb').write(data)
print(len(seeds))
