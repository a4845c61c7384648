# The elastic column of make_recorders.py in OpenSees (Tcl): the script whose output
# the files next to it are. Run with OpenSees 3.x: `OpenSees column.tcl`.
# Units: N, m, s, kg, Pa. 1 m wide, 2 m high, 2 × 4 FourNodeQuad elements of 0.5 m.
wipe
model BasicBuilder -ndm 2 -ndf 2

set rho 2000.0; set E 20.0e6; set nu 0.25; set g 9.81
for {set j 0} {$j <= 4} {incr j} {
  for {set i 0} {$i <= 2} {incr i} {
    node [expr 1 + $i + 3*$j] [expr 0.5*$i] [expr 0.5*$j]
  }
}
fix 1 1 1; fix 2 0 1; fix 3 1 1                        ;# roller base, corners fixed
for {set j 1} {$j <= 4} {incr j} { fix [expr 1 + 3*$j] 1 0; fix [expr 3 + 3*$j] 1 0 }

nDMaterial ElasticIsotropic 1 $E $nu $rho
for {set j 0} {$j < 4} {incr j} {
  for {set i 0} {$i < 2} {incr i} {
    set n1 [expr 1 + $i + 3*$j]
    # thickness, type, material, surface pressure, mass density (0: the material's),
    # body force per unit volume b1 b2 = 0, −ρg
    element quad [expr 1 + $i + 2*$j] $n1 [expr $n1 + 1] [expr $n1 + 4] [expr $n1 + 3] \
      1.0 "PlaneStrain" 1 0.0 0.0 0.0 [expr -$rho*$g]
  }
}
print -JSON -file model.json

# The recorders opensees2fem reads (tools/interop/README.md): every node, every element,
# in increasing tag order, with the time column, 16 digits.
recorder Node -file disp.out -time -precision 16 -nodeRange 1 15 -dof 1 2 disp
recorder Node -file vel.out -time -precision 16 -nodeRange 1 15 -dof 1 2 vel
recorder Node -file accel.out -time -precision 16 -nodeRange 1 15 -dof 1 2 accel
recorder Element -file stress.out -time -precision 16 -eleRange 1 8 stress
recorder Element -file strain.out -time -precision 16 -eleRange 1 8 strain

# Gravity in two load steps (t = 0.5, 1).
pattern Plain 1 Linear { }                          ;# the body force is in the elements
constraints Transformation; numberer RCM; system BandGeneral
test NormDispIncr 1e-12 20; algorithm Newton
integrator LoadControl 0.5; analysis Static
analyze 2

# The failure stage starts here: the clock goes back to 0 and the state is recorded once.
loadConst -time 0.0
record
wipeAnalysis
constraints Transformation; numberer RCM; system BandGeneral
test NormDispIncr 1e-12 20; algorithm Newton
integrator Newmark 0.5 0.25; analysis Transient
analyze 2 0.01
