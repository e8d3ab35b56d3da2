!> The Gauss-Legendre rules through the thickness, n = 1..9 points: column n holds the n points
!> (in [-1, 1], ascending; rows beyond n are 0) and their weights (summing to 2). They are the
!> values that a Newton iteration on the Legendre polynomial P_n gives, to the last bit (the engine
!> used to compute them for every element group of every step; a table is the same numbers
!> without the 4 % of the time loop that cost). tests/test_kernels_blt.py checks them against
!> numpy's leggauss.
module gauss_legendre
  use paradyn_kinds, only: wp
  ! a schema with more points fails to compile here until the table has them
  use paradyn_schema, only: max_integration_points
  implicit none
  private
  public :: gauss_zeta, gauss_weight

  real(wp), parameter :: gauss_zeta(max_integration_points, max_integration_points) = reshape([ &
    -6.1232339957367660e-17_wp, 0.0_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    -5.7735026918962573e-1_wp, 5.7735026918962573e-1_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    -7.7459666924148340e-1_wp, -6.1232339957367660e-17_wp, 7.7459666924148340e-1_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    -8.6113631159405257e-1_wp, -3.3998104358485626e-1_wp, 3.3998104358485626e-1_wp, &
    8.6113631159405257e-1_wp, 0.0_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    -9.0617984593866396e-1_wp, -5.3846931010568311e-1_wp, 0.0000000000000000e0_wp, &
    5.3846931010568311e-1_wp, 9.0617984593866396e-1_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    -9.3246951420315205e-1_wp, -6.6120938646626448e-1_wp, -2.3861918608319690e-1_wp, &
    2.3861918608319690e-1_wp, 6.6120938646626448e-1_wp, 9.3246951420315205e-1_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    -9.4910791234275849e-1_wp, -7.4153118559939446e-1_wp, -4.0584515137739718e-1_wp, &
    0.0000000000000000e0_wp, 4.0584515137739718e-1_wp, 7.4153118559939446e-1_wp, &
    9.4910791234275849e-1_wp, 0.0_wp, 0.0_wp, &
    -9.6028985649753618e-1_wp, -7.9666647741362673e-1_wp, -5.2553240991632899e-1_wp, &
    -1.8343464249564986e-1_wp, 1.8343464249564986e-1_wp, 5.2553240991632899e-1_wp, &
    7.9666647741362673e-1_wp, 9.6028985649753618e-1_wp, 0.0_wp, &
    -9.6816023950762609e-1_wp, -8.3603110732663577e-1_wp, -6.1337143270059036e-1_wp, &
    -3.2425342340380897e-1_wp, -6.1232339957367660e-17_wp, 3.2425342340380897e-1_wp, &
    6.1337143270059036e-1_wp, 8.3603110732663577e-1_wp, 9.6816023950762609e-1_wp], [max_integration_points, max_integration_points])
  real(wp), parameter :: gauss_weight(max_integration_points, max_integration_points) = reshape([ &
    2.0000000000000000e0_wp, 0.0_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    1.0000000000000002e0_wp, 1.0000000000000002e0_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    5.5555555555555525e-1_wp, 8.8888888888888884e-1_wp, 5.5555555555555525e-1_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    3.4785484513745374e-1_wp, 6.5214515486254643e-1_wp, 6.5214515486254643e-1_wp, &
    3.4785484513745374e-1_wp, 0.0_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    2.3692688505618900e-1_wp, 4.7862867049936647e-1_wp, 5.6888888888888889e-1_wp, &
    4.7862867049936647e-1_wp, 2.3692688505618900e-1_wp, 0.0_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    1.7132449237917050e-1_wp, 3.6076157304813855e-1_wp, 4.6791393457269126e-1_wp, &
    4.6791393457269126e-1_wp, 3.6076157304813855e-1_wp, 1.7132449237917050e-1_wp, &
    0.0_wp, 0.0_wp, 0.0_wp, &
    1.2948496616886968e-1_wp, 2.7970539148927670e-1_wp, 3.8183005050511903e-1_wp, &
    4.1795918367346940e-1_wp, 3.8183005050511903e-1_wp, 2.7970539148927670e-1_wp, &
    1.2948496616886968e-1_wp, 0.0_wp, 0.0_wp, &
    1.0122853629037649e-1_wp, 2.2238103445337437e-1_wp, 3.1370664587788738e-1_wp, &
    3.6268378337836199e-1_wp, 3.6268378337836199e-1_wp, 3.1370664587788738e-1_wp, &
    2.2238103445337437e-1_wp, 1.0122853629037649e-1_wp, 0.0_wp, &
    8.1274388361574634e-2_wp, 1.8064816069485751e-1_wp, 2.6061069640293544e-1_wp, &
    3.1234707704000292e-1_wp, 3.3023935500125978e-1_wp, 3.1234707704000292e-1_wp, &
    2.6061069640293544e-1_wp, 1.8064816069485751e-1_wp, 8.1274388361574634e-2_wp], [max_integration_points, max_integration_points])

end module gauss_legendre
