#!/usr/bin/env python3
"""docs/design.md "Extended emitters: feedback": the exact cases φ = kθ + c
(the smooth emitter of the CLI test, 100 cd·sin² from the cone's edge)
designed and traced with a point source (one feedback iteration, to see
that it changes nothing beyond noise) and with dies of 4 × 4 and 10 × 10 mm
(three iterations, 10^6 rays), 10^6 photons each. One JSON line per run, in
the working folder: report.json's feedback per iteration and the profile
against the closed form.

    cd SCRATCH && python3 /path/to/scripts/design_feedback_table.py > results.jsonl
"""
import json, math, pathlib, subprocess, sys, time
G = str(pathlib.Path(__file__).resolve().parents[1] / "build" / "tools" / "gonio")
def emitter(path, frm):
    g=[0.5*i for i in range(361)]
    c=[0 if x<frm else 100*math.sin(math.pi/2*(x-frm)/(180-frm))**2 for x in g]
    lines=["IESNA:LM-63-2002","[TEST] x","[TESTLAB] x","[ISSUEDATE] x","[MANUFAC] x","TILT=NONE",f"1 -1 1 {len(g)} 1 1 2 0 0 0","1 1 0"]
    for i in range(0,len(g),10): lines.append(" ".join(f"{x:g}" for x in g[i:i+10]))
    lines.append("0")
    for i in range(0,len(c),10): lines.append(" ".join(f"{x:.6g}" for x in c[i:i+10]))
    open(path,"w").write("\n".join(lines)+"\n")
def exact_r(k,c,theta,to,dist):
    f=lambda t: abs(math.sin(((k-1)*t+c)/2))**(2/(k-1))
    return dist*f(theta)/f(to)
cases=[(-1,180,100,'uncrossed'),(-0.5,90,70,'uncrossed'),(0.5,-90,60,'crossed'),(2,-360,140,'crossed')]
for k,c,frm,m in cases:
    emitter(f'e{frm}.ies',frm)
    for die in ['point','4x4','10x10']:
        out=f'k{k}_{die}'
        args=[G,'design','reflector','--emitter',f'e{frm}.ies','--target',f'linear:{k},{c}','--cone',f'{frm},180','--map',m,'--out',out,'--photons','1000000']
        if die!='point': args+=['--die',die,'--die-rays','1000000','--feedback','3']
        else: args+=['--feedback','1']
        t=time.time(); r=subprocess.run(args,capture_output=True,text=True); dt=time.time()-t
        if r.returncode: print(k,die,'FAILED',r.stderr[-500:]); continue
        d=json.load(open(out+'/report.json'))['design']
        th=d['profile']['theta_deg']; rr=d['profile']['r_mm']
        prof=max(abs(rr[i]/(1e3*exact_r(k,c*math.pi/180,th[i]*math.pi/180,math.pi,0.02))-1) for i in range(len(th)))
        it=d['feedback']['per_iteration']
        print(json.dumps(dict(k=k,c=c,cone=frm,map=m,die=die,kept=d['feedback']['kept'],profile_vs_closed_form=prof,
          rms_c_mean=[x['rms_relative_c_mean'] for x in it], rms=[x['rms_relative'] for x in it], maxc=[x['max_relative_c_mean'] for x in it],
          beam=[x['beam_angle_traced_deg'] for x in it], beam_target=d['against_target']['beam_angle_target_deg'],
          changes=[x.get('profile_change_next') for x in it], wall=dt)), flush=True)
