#!/usr/bin/env python3
"""Pairs two `garmcap rig eval` outputs case by case (stdout saved to a file, stderr apart) and
prints, over the cases of the second, each case's type and errors in both and the per-measurement
mean / max absolute error (n readings, missing) of each. Used for the cut-against-uncut tables of
docs/measurement_model.md ("Forms cut by the frame"):

    garmcap rig eval RIG > full.eval;  garmcap rig eval CUT > cut.eval
    python3 capture/sim/physical/compare_evals.py full.eval cut.eval
"""
import json,sys
def load(p):
    rows={}
    for line in open(p):
        line=line.strip()
        if line.startswith('{') and '"id"' in line[:400] and not line.startswith('{"summary'):
            i=line.find('}garmcap: error')
            line=line[:i+1] if i>0 else line
            r=json.loads(line); rows[r["id"]]=r
    return rows
a=load(sys.argv[1]); b=load(sys.argv[2])
ids=[i for i in b if i in a]
stats={}
for i in ids:
    ra,rb=a[i],b[i]
    print(i, ra.get('truth_type'), 'full:',ra.get('type'), 'cut:',rb.get('type'), rb.get('error','')[:90])
    for tag,r in (('full',ra),('cut',rb)):
        for k,e in r.get('error_cm',{}).items():
            stats.setdefault(k,{}).setdefault(tag,[]).append(abs(e))
        missing = list(r.get('missing',[]))
        if 'error' in r:  # a failed case: every reading the other one has is missing
            other = rb if tag == 'full' else ra
            missing += list(other.get('error_cm',{})) + list(other.get('missing',[]))
        for k in missing:
            stats.setdefault(k,{}).setdefault(tag+'_miss',[]).append(1)
    d={k:(ra.get('error_cm',{}).get(k),rb.get('error_cm',{}).get(k)) for k in set(ra.get('error_cm',{}))|set(rb.get('error_cm',{}))}
    print('   ', {k:v for k,v in sorted(d.items())})
print('%-18s %18s %18s'%('measurement','full mean/max (n,miss)','cut mean/max (n,miss)'))
for k,s in sorted(stats.items()):
    def f(t):
        v=s.get(t,[]); m=len(s.get(t+'_miss',[]))
        return '%.2f / %.2f (%d,%d)'%(sum(v)/len(v),max(v),len(v),m) if v else '- (0,%d)'%m
    print('%-18s %22s %22s'%(k,f('full'),f('cut')))
