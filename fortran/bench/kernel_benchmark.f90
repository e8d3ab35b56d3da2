!> paradyn-kernel-benchmark [ELEMENTS] [CYCLES] [ONLY]
!>
!> ONLY, when given, runs only the lines whose label contains it (e.g. 'fully integrated', or
!> 'update' for the stress update alone): a profiler then sees one case.
!>
!> Times the BLT element kernel alone, single thread, on groups of the engine's size: an elastic
!> section (with and without the warping correction), a J2-plastic section that yields and a
!> piecewise-linear one (MAT_024: a 4-point hardening curve, with and without Cowper-Symonds rates),
!> the fully integrated element (shell_full) elastic and plastic, and its CPU time over the
!> one-point element's with the two run in turn (interleaved_ratio), all with 5 through-thickness
!> points; then the plastic members' stress update alone, on batches
!> of 64 points that stay plastic (nanoseconds of CPU time per point update, the least of 5 rounds,
!> and each piecewise member's ratio to its J2 twin: J2 with hardening, j2_rate). Prints microseconds per element-cycle, of wall time and of the
!> process's CPU time (the second is steadier on a shared machine, where another process can take
!> the core away). Gathers and the nodal sum are not included (the engine's element-cycles per
!> second include them).
program kernel_benchmark
  use paradyn_kinds, only: wp, ek, i8
  use shell_section, only: shell_properties_t, stress_components, hourglass_components
  use shell_blt, only: blt_internal_forces
  use shell_full, only: full_internal_forces
  use shell_c0_triangle, only: c0_triangle_internal_forces
  use material_factory, only: material_from_deck
  use deck_fields, only: deck_fields_t
  use element_groups, only: group_size
  use paradyn_schema, only: hourglass_stiffness, hourglass_physical, material_elastic, material_j2_plasticity, &
                            material_j2_rate, material_piecewise_linear, material_piecewise_linear_rate
  use material_model, only: material_t
  implicit none
  !> the state of the benchmark's groups of elements (arrays by group last)
  type :: bench_groups_t
    real(wp), allocatable :: x(:, :, :, :), v(:, :, :, :), w(:, :, :, :), force(:, :, :)
    real(ek), allocatable :: stress(:, :, :, :), back(:, :, :, :), eps_p(:, :, :), hg(:, :, :)   !< element state: kind ek
    real(ek), allocatable :: state(:, :, :, :)   !< the material member's own state per point
    real(wp), allocatable :: e_int(:, :), e_hg(:, :)
    integer :: inverted = 0
  end type bench_groups_t
  integer :: n_elements, n_cycles, n_groups
  integer :: triangle_every = 0   !< every this many groups is one of triangles (0: none)
  character(len=32) :: arg
  character(len=64) :: only = ''   !< run only the lines whose label contains this (empty: all)
  character(len=64) :: label
  type(shell_properties_t) :: props
  integer :: seed_size, s
  character(len=48) :: names(5)
  integer :: twin(5), round, k
  real(wp) :: best(5)
  integer, allocatable :: seed(:)

  n_elements = 16384
  n_cycles = 200
  if (command_argument_count() >= 1) then
    call get_command_argument(1, arg)
    read (arg, *) n_elements
  end if
  if (command_argument_count() >= 2) then
    call get_command_argument(2, arg)
    read (arg, *) n_cycles
  end if
  if (command_argument_count() >= 3) call get_command_argument(3, only)
  n_groups = max(1, n_elements / group_size)
  call random_seed(size=seed_size)   ! the same elements every run: the state bits compare builds
  seed = [(1234567 + 7919 * s, s = 1, seed_size)]
  call random_seed(put=seed)
  props%thickness = 0.003_wp
  props%density = 7860.0_wp
  props%young = 200.0e9_wp
  props%poisson = 0.28_wp
  props%hourglass_coefficient = 0.1_wp
  props%integration_points = 5
  call material_from_deck(steel(material_elastic), 1, props%material)
  write (*, '(a,i0,a,i0,a,i0,3a)') 'BLT kernel, ', n_groups * group_size, ' elements in groups of ', &
    group_size, ', ', n_cycles, ' cycles, 1 thread, 5 points, element kernel in ', &
    trim(merge('double', 'single', ek == wp)), ' precision'
  call report('elastic: ', props)
  props%warping_correction = .false.   ! the elements are warped (1e-4 m on 1 cm): the correction's cost
  call report('elastic, no warping correction: ', props)
  props%warping_correction = .true.
  props%hourglass_form = hourglass_stiffness   ! the physical form's cost against the stiffness form's
  call report('elastic, stiffness hourglass form: ', props)
  props%hourglass_form = hourglass_physical
  call material_from_deck(steel(material_j2_plasticity), 1, props%material)
  call report('plastic: ', props)
  props%fully_integrated = .true.   ! the fully integrated element (4 x 5 points, no hourglass control)
  call material_from_deck(steel(material_elastic), 1, props%material)
  call report('elastic, fully integrated: ', props)
  call material_from_deck(steel(material_j2_plasticity), 1, props%material)
  call report('plastic, fully integrated: ', props)
  props%fully_integrated = .false.
  ! the two elements' ratio, interleaved (the lines above are measured seconds apart)
  do s = 1, 2
    label = trim(merge('elastic', 'plastic', s == 1))//', fully integrated / one-point, interleaved'
    if (.not. selected(label)) cycle
    call material_from_deck(steel(merge(material_elastic, material_j2_plasticity, s == 1)), 1, props%material)
    write (*, '(2a,f7.3,a)') trim(label), ': ', interleaved_ratio(props), ' (CPU time, median of 10 rounds)'
  end do
  do s = 1, 2   ! the triangles: all groups, then every tenth
    triangle_every = merge(1, 10, s == 1)
    call material_from_deck(steel(material_elastic), 1, props%material)
    call report(trim(merge('elastic, triangles:      ', 'elastic, 10 % triangles: ', s == 1))//' ', props)
    call material_from_deck(steel(material_j2_plasticity), 1, props%material)
    call report(trim(merge('plastic, triangles:      ', 'plastic, 10 % triangles: ', s == 1))//' ', props)
  end do
  triangle_every = 0   ! the materials below on quadrilaterals
  call material_from_deck(steel(material_piecewise_linear), 1, props%material)
  call report('plastic, piecewise_linear (4-point curve): ', props)
  call material_from_deck(steel(material_piecewise_linear_rate), 1, props%material)
  call report('plastic, piecewise_linear_rate (curve, Cowper-Symonds): ', props)
  ! the stress update alone: the members in turn, 5 rounds; the least time of each (a shared
  ! machine only ever adds time) and its ratio to its J2 twin's
  if (.not. selected('stress update alone')) stop
  names = [character(len=48) :: 'j2_plasticity (perfectly plastic)', 'j2_plasticity (Et = 2 GPa)', 'j2_rate', &
           'piecewise_linear (4-point curve)', 'piecewise_linear_rate (curve, Cowper-Symonds)']
  twin = [0, 0, 0, 2, 3]
  best = huge(1.0_wp)
  do round = 1, 5
    do k = 1, size(names)
      best(k) = min(best(k), point_update(member_deck(k)))
    end do
  end do
  write (*, '(a)') 'stress update alone, 64-point batches, every point plastic: least of 5 rounds'
  do k = 1, size(names)
    if (twin(k) > 0) then
      write (*, '(2x,a,f8.2,a,f6.3,2a)') names(k), best(k), ' ns per point update, ', best(k) / best(twin(k)), &
        ' x ', trim(names(twin(k)))
    else
      write (*, '(2x,a,f8.2,a)') names(k), best(k), ' ns per point update'
    end if
  end do

contains

  !> A deck of one steel of the given material model (J2: perfectly plastic at 250 MPa; the
  !> piecewise members: the curve 250, 300, 330, 400 MPa at plastic strains 0, 0.01, 0.03, 0.08;
  !> rates: mild steel's C = 40.4 1/s, P = 5).
  function steel(model) result(deck)
    integer, intent(in) :: model
    type(deck_fields_t) :: deck
    deck = deck_fields_t(material_model=[model], young=[props%young], poisson=[props%poisson], &
                         yield_stress=[250.0e6_wp], tangent_modulus=[0.0_wp], hardening_mixing=[1.0_wp], &
                         rate_c=[40.4_wp], rate_p=[5.0_wp], hardening_curve=[1], rate_curve=[0], &
                         n_curves=1, n_curve_points=4, curve_first_point=[1], &
                         curve_time=[0.0_wp, 0.01_wp, 0.03_wp, 0.08_wp], &
                         curve_value=[250.0e6_wp, 300.0e6_wp, 330.0e6_wp, 400.0e6_wp])
  end function steel

  !> The deck of benchmarked member k: J2 perfectly plastic, J2 with Et = 2 GPa (H = 2.02 GPa,
  !> about the curve's mean slope), j2_rate, piecewise_linear, piecewise_linear_rate
  function member_deck(k) result(deck)
    integer, intent(in) :: k
    type(deck_fields_t) :: deck
    integer, parameter :: models(5) = [material_j2_plasticity, material_j2_plasticity, material_j2_rate, &
                                       material_piecewise_linear, material_piecewise_linear_rate]
    deck = steel(models(k))
    if (k == 2) deck%tangent_modulus = [2.0e9_wp]
  end function member_deck

  !> Nanoseconds of CPU time per point update of the member of `deck` alone: ELEMENTS / 64 batches
  !> of 64 points (256 by default), each point a fixed random strain increment of about 2e-4 per
  !> 1e-7 s step (a rate of about 2000 1/s) for CYCLES steps (200), plastic from the third
  !> (negative if a point did not yield).
  function point_update(deck) result(ns)
    type(deck_fields_t), intent(in) :: deck
    real(wp) :: ns
    integer, parameter :: m = 64
    integer :: batches, steps
    class(material_t), allocatable :: material
    real(ek), allocatable :: stress(:, :, :), back(:, :, :), eps_p(:, :), state(:, :, :), dstrain(:, :, :)
    real(wp) :: r(3), cpu0, cpu1
    integer :: b, i, step
    batches = n_groups   ! the element lines' sizes: 256 batches of 64 points, 200 steps by default
    steps = n_cycles
    call material_from_deck(deck, 1, material)
    allocate (stress(m, 3, batches), back(m, 3, batches), eps_p(m, batches), dstrain(m, 3, batches), source=0.0_ek)
    allocate (state(m, material%state_width(), batches), source=0.0_ek)
    call random_seed(put=seed)   ! the same increments for every member
    do b = 1, batches
      do i = 1, m
        call random_number(r)
        dstrain(i, :, b) = real(2.0e-4_wp * [1.0_wp, r(2) - 0.8_wp, r(3) - 0.5_wp], ek)
      end do
    end do
    call cpu_time(cpu0)
    do step = 1, steps
      do b = 1, batches
        call material%update_points(m, 1.0e-7_ek, stress(:, :, b), back(:, :, b), eps_p(:, b), state(:, :, b), &
                                    dstrain(:, :, b))
      end do
    end do
    call cpu_time(cpu1)
    ns = 1.0e9_wp * (cpu1 - cpu0) / (real(steps, wp) * batches * m)
    if (minval(eps_p) <= 0.0_ek) ns = -1.0_wp
  end function point_update

  logical function selected(label)
    character(len=*), intent(in) :: label
    selected = len_trim(only) == 0 .or. index(label, trim(only)) > 0
  end function selected

  subroutine report(label, p)
    character(len=*), intent(in) :: label
    type(shell_properties_t), intent(in) :: p
    real(wp) :: us(2)
    integer(i8) :: bits
    if (.not. selected(label)) return
    us = time_per_element_cycle(p, bits)
    write (*, '(a,f8.4,a,f8.4,a,z16.16)') label, us(1), ' us per element-cycle (', us(2), &
      ' us CPU time), state bits ', bits
  end subroutine report

  !> wall and CPU time per element-cycle in microseconds; negative when the run went wrong. bits:
  !> the exclusive or of the bit patterns of the final state and forces, equal for two builds whose
  !> kernels compute bitwise the same
  function time_per_element_cycle(p, bits) result(us)
    type(shell_properties_t), intent(in) :: p
    integer(i8), intent(out) :: bits
    real(wp) :: us(2)
    type(bench_groups_t) :: b
    integer :: c
    integer(i8) :: t0, t1, rate
    real(wp) :: cpu0, cpu1
    call set_up(p, b)
    call system_clock(t0, rate)
    call cpu_time(cpu0)
    do c = 1, n_cycles
      call one_cycle(p, b)
    end do
    call cpu_time(cpu1)
    call system_clock(t1)
    us(1) = 1.0e6_wp * real(t1 - t0, wp) / real(rate, wp) / (real(n_cycles, wp) * n_groups * group_size)
    us(2) = 1.0e6_wp * (cpu1 - cpu0) / (real(n_cycles, wp) * n_groups * group_size)
    bits = ieor(ieor(xor_state_bits(b%stress, size(b%stress)), xor_state_bits(b%back, size(b%back))), &
                ieor(xor_state_bits(b%eps_p, size(b%eps_p)), xor_state_bits(b%hg, size(b%hg))))
    bits = ieor(ieor(bits, xor_bits(b%e_int, size(b%e_int))), &
                ieor(xor_bits(b%e_hg, size(b%e_hg)), xor_bits(b%force, size(b%force))))
    if (.not. sound(p, b)) us = -1.0_wp
  end function time_per_element_cycle

  !> The fully integrated element's CPU time per element-cycle over the one-point element's, the
  !> two run in turn, a block of cycles each, so that both see the same machine (on a shared one
  !> the speed of a core drifts over seconds, more than these kernels differ by): 10 rounds, each
  !> of one untimed cycle (the other element's state has just passed through the caches) and
  !> n_cycles / 10 timed ones per element; the median of the rounds' ratios. Negative when a run
  !> went wrong.
  function interleaved_ratio(p) result(ratio)
    type(shell_properties_t), intent(in) :: p
    real(wp) :: ratio
    integer, parameter :: rounds = 10
    type(shell_properties_t) :: one_point, full
    type(bench_groups_t) :: b_one, b_full
    real(wp) :: ratios(rounds)
    integer :: round, block
    one_point = p
    one_point%fully_integrated = .false.
    full = p
    full%fully_integrated = .true.
    call set_up(one_point, b_one)
    call set_up(full, b_full)
    block = max(1, n_cycles / rounds)
    do round = 1, rounds
      ratios(round) = block_time(full, b_full, block) / block_time(one_point, b_one, block)
    end do
    ratio = median(ratios)
    if (.not. (sound(one_point, b_one) .and. sound(full, b_full))) ratio = -1.0_wp
  end function interleaved_ratio

  !> CPU time of `cycles` cycles of every group of b, after one untimed cycle
  real(wp) function block_time(p, b, cycles) result(seconds)
    type(shell_properties_t), intent(in) :: p
    type(bench_groups_t), intent(inout) :: b
    integer, intent(in) :: cycles
    real(wp) :: cpu0, cpu1
    integer :: c
    call one_cycle(p, b)
    call cpu_time(cpu0)
    do c = 1, cycles
      call one_cycle(p, b)
    end do
    call cpu_time(cpu1)
    seconds = cpu1 - cpu0
  end function block_time

  !> The benchmark's groups of elements: a 1 cm square, warped by up to 1e-4 m, with random nodal
  !> velocities (strain rates large enough to yield) and rotation rates, state at zero
  subroutine set_up(p, b)
    type(shell_properties_t), intent(in) :: p
    type(bench_groups_t), intent(out) :: b
    real(wp) :: r(3)
    integer :: g, i, k, pts
    allocate (b%x(group_size, 3, 4, n_groups), b%v(group_size, 3, 4, n_groups), b%w(group_size, 3, 4, n_groups))
    pts = 5 * merge(4, 1, p%fully_integrated)   ! stored points: a fully integrated element's 4 in-plane
    ! the back stress only where the material keeps one, as element_state allocates it
    allocate (b%stress(group_size, stress_components, pts, n_groups), source=0.0_ek)
    allocate (b%back(group_size, 3, p%material%back_stress_points(pts), n_groups), source=0.0_ek)
    allocate (b%eps_p(group_size, pts, n_groups), b%hg(group_size, hourglass_components, n_groups), source=0.0_ek)
    allocate (b%state(group_size, p%material%state_width(), pts, n_groups), source=0.0_ek)
    allocate (b%e_int(group_size, n_groups), b%e_hg(group_size, n_groups), source=0.0_wp)
    allocate (b%force(6, 4, group_size))
    do g = 1, n_groups
      do i = 1, group_size
        do k = 1, 4
          call random_number(r)
          b%x(i, :, k, g) = 0.01_wp * [merge(0.0_wp, 1.0_wp, k == 1 .or. k == 4), &
                                       merge(0.0_wp, 1.0_wp, k <= 2), 0.0_wp] + 1.0e-4_wp * r
          call random_number(r)
          b%v(i, :, k, g) = 20.0_wp * (r - 0.5_wp)   ! strain rates large enough to yield
          call random_number(r)
          b%w(i, :, k, g) = 100.0_wp * (r - 0.5_wp)
        end do
      end do
    end do
    if (triangle_every > 0) then
      do g = triangle_every, n_groups, triangle_every
        b%x(:, :, 4, g) = b%x(:, :, 3, g)
      end do
    end if
  end subroutine set_up

  !> One step of every group of b with the element p asks for
  subroutine one_cycle(p, b)
    type(shell_properties_t), intent(in) :: p
    type(bench_groups_t), intent(inout) :: b
    real(wp) :: dt_element(group_size)
    integer :: g
    do g = 1, n_groups
      if (triangle_every > 0) then
        if (modulo(g, triangle_every) == 0) then
          call c0_triangle_internal_forces(group_size, b%x(:, :, :, g), b%v(:, :, :, g), b%w(:, :, :, g), p, 1.0e-7_wp, &
                                           b%stress(:, :, :, g), b%back(:, :, :, g), b%eps_p(:, :, g), b%state(:, :, :, g), &
                                           b%hg(:, :, g), b%force, b%e_int(:, g), b%e_hg(:, g), b%inverted, dt_element)
          cycle
        end if
      end if
      if (p%fully_integrated) then
        call full_internal_forces(group_size, b%x(:, :, :, g), b%v(:, :, :, g), b%w(:, :, :, g), p, 1.0e-7_wp, &
                                  b%stress(:, :, :, g), b%back(:, :, :, g), b%eps_p(:, :, g), b%state(:, :, :, g), &
                                  b%hg(:, :, g), b%force, b%e_int(:, g), b%inverted, dt_element)
        cycle
      end if
      call blt_internal_forces(group_size, b%x(:, :, :, g), b%v(:, :, :, g), b%w(:, :, :, g), p, 1.0e-7_wp, &
                               b%stress(:, :, :, g), b%back(:, :, :, g), b%eps_p(:, :, g), b%state(:, :, :, g), &
                               b%hg(:, :, g), b%force, b%e_int(:, g), b%e_hg(:, g), b%inverted, dt_element)
    end do
  end subroutine one_cycle

  !> The median of values (the mean of the middle two for an even count)
  pure real(wp) function median(values)
    real(wp), intent(in) :: values(:)
    real(wp) :: sorted(size(values)), swap
    integer :: i, j, n
    sorted = values
    n = size(values)
    do i = 2, n   ! insertion sort: a handful of values
      swap = sorted(i)
      j = i - 1
      do while (j >= 1)
        if (sorted(j) <= swap) exit
        sorted(j + 1) = sorted(j)
        j = j - 1
      end do
      sorted(j + 1) = swap
    end do
    median = 0.5_wp * (sorted((n + 1) / 2) + sorted(n / 2 + 1))
  end function median

  !> No element inverted, finite energies, and a material with history has yielded
  logical function sound(p, b)
    type(shell_properties_t), intent(in) :: p
    type(bench_groups_t), intent(in) :: b
    sound = b%inverted == 0 .and. sum(b%e_int) == sum(b%e_int)
    if (p%material%has_history()) sound = sound .and. maxval(b%eps_p) > 0.0_ek   ! must have yielded
  end function sound

  !> the exclusive or of the bit patterns of a(1:n), each rotated by its position
  integer(i8) function xor_bits(a, n) result(bits)
    integer, intent(in) :: n
    real(wp), intent(in) :: a(n)   !< a whole contiguous array of any rank (sequence association)
    integer :: i
    bits = 0
    do i = 1, n
      bits = ieor(ishftc(bits, 1), transfer(a(i), bits))
    end do
  end function xor_bits

  !> xor_bits of element state (the kernel's kind ek), each value widened to double
  integer(i8) function xor_state_bits(a, n) result(bits)
    integer, intent(in) :: n
    real(ek), intent(in) :: a(n)
    integer :: i
    bits = 0
    do i = 1, n
      bits = ieor(ishftc(bits, 1), transfer(real(a(i), wp), bits))
    end do
  end function xor_state_bits

end program kernel_benchmark
