"""compare.py A B: the outputs of tools/outputs/run_examples.sh in A and B, file by file."""
import os,sys,json,re,filecmp
a,b=os.path.abspath(sys.argv[1]),os.path.abspath(sys.argv[2])
ROOTS=re.compile(re.escape(a)+"|"+re.escape(b))
TIME=re.compile(r'(wall|seconds|elapsed|_s$|time_s|wall_time)')
def norm(x):
    if isinstance(x,str): return ROOTS.sub("OUT",x)
    if isinstance(x,dict): return {k:norm(v) for k,v in x.items() if not re.search(r'wall|seconds|elapsed|wall_time_s|compute_s',k)}
    if isinstance(x,list): return [norm(v) for v in x]
    return x
same=0; diff=[]
for root,_,files in os.walk(a):
    for f in files:
        pa=os.path.join(root,f); rel=os.path.relpath(pa,a); pb=os.path.join(b,rel)
        if not os.path.exists(pb): diff.append(('missing',rel)); continue
        if filecmp.cmp(pa,pb,shallow=False): same+=1; continue
        if f.endswith('.json') or f.endswith('.stdout'):
            try:
                if norm(json.load(open(pa)))==norm(json.load(open(pb))): same+=1; continue
            except Exception: pass
        if f.endswith('.stderr') or f.endswith('.stdout') or f.endswith('.txt') or f.endswith('.html'):
            ta=re.sub(r'\d+\.\d+ s\b','X s',open(pa,errors='replace').read()); tb=re.sub(r'\d+\.\d+ s\b','X s',open(pb,errors='replace').read())
            ta=ROOTS.sub('OUT',ta); tb=ROOTS.sub('OUT',tb)
            if ta==tb: same+=1; continue
        diff.append(('differs',rel))
for root,_,files in os.walk(b):
    for f in files:
        rel=os.path.relpath(os.path.join(root,f),b)
        if not os.path.exists(os.path.join(a,rel)): diff.append(('extra',rel))
print(same,'identical (modulo wall-clock fields)'); [print(*d) for d in diff]
