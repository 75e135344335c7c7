# A goalkeeper on a three-wheel omni base: an elliptic body wide across the
# goal (0.36 x 0.50 m), with a kicker to clear the ball. Units: m, kg, s, rad.
mass 15
shape ellipse rx=0.18 ry=0.25 z=0,0.5

kicker direction=0 reach=0.03 {
  state rest { shape rect x=0.19 length=0.03 width=0.26 z=0.02,0.14 }
  state kick accel=250 contact=0.02 hold=0.25 next=rest {
    shape rect x=0.25 length=0.15 width=0.26 z=0.02,0.14
  }
}

motion omni_drive radius=0.17 wheel_speed=2.5 wheel_accel=8

sensor odometry translation_noise=0.01 rotation_noise=0.02
sensor camera name=front fov=1.6 range=6 z=0.5 range_noise=0.02 bearing_noise=0.01
