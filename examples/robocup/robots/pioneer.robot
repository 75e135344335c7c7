# An F2000 field player of the Pioneer kind: a 0.44 x 0.38 m differential
# base, 0.6 m tall, with a pneumatic kicker in front. Units: m, kg, s, rad.
mass 20
shape rect length=0.44 width=0.38 z=0,0.6

# The kicker plate rests at the front (x 0.22..0.25); a kick pushes it out
# 13 cm for a quarter of a second. A ball touching the plate when it fires
# gains accel * contact = 300 * 0.02 = 6 m/s.
kicker direction=0 reach=0.03 {
  state rest { shape rect x=0.235 length=0.03 width=0.28 z=0.02,0.14 }
  state kick accel=300 contact=0.02 hold=0.25 next=rest {
    shape rect x=0.30 length=0.16 width=0.28 z=0.02,0.14
  }
}

motion diff_drive max_speed=2 max_turn=6 accel=2.5 turn_accel=15

sensor odometry translation_noise=0.01 rotation_noise=0.02 drift=0.01
sensor omnivision name=omni range=5 z=0.7 range_noise=0.02 bearing_noise=0.01 period=4
sensor laser name=laser mode=raw beams=181 range=8 z=0.3 noise=0.01 period=10
sensor ultrasonic name=sonar cone=0.5 range=3 z=0.15 period=5
