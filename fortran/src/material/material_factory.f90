!> Makes a member of the material family for one material of the deck, by its schema name (the
!> deck's fields: deck_fields, generated from the schema, so a member's new parameter is a dataset
!> in schema/deck.toml and nothing more here). Adding a member: its module, a case here, and its
!> name in the schema's enum material_model (with its traits, e.g. plastic).
module material_factory
  use paradyn_schema, only: enum_name, enum_material_model
  use deck_fields, only: deck_fields_t
  use material_model, only: material_t, max_state_words
  use elastic_material, only: elastic_material_t
  use j2_material, only: j2_material_t
  use j2_rate_material, only: j2_rate_material_t
  use j2_radial_material, only: j2_radial_material_t
  use piecewise_linear_material, only: piecewise_linear_material_t, piecewise_linear_from_curve, rate_none, &
                                       rate_cowper_symonds, rate_tabulated
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: material_from_deck

contains

  !> The member for material m of deck; not allocated for an unknown name or a member that
  !> would keep more state per point than the element state holds (max_state_words).
  subroutine material_from_deck(deck, m, material)
    class(deck_fields_t), intent(in) :: deck
    integer, intent(in) :: m
    class(material_t), allocatable, intent(out) :: material
    select case (enum_name(enum_material_model, deck%material_model(m)))
    case ('elastic', 'rigid')   ! a rigid part has no stress: its elastic constants set the contact stiffness
      allocate (material, source=elastic_material_t(young=deck%young(m), poisson=deck%poisson(m)))
    case ('j2_plasticity')
      allocate (material, source=j2_material_t(young=deck%young(m), poisson=deck%poisson(m), &
                                               yield_stress=deck%yield_stress(m), &
                                               tangent_modulus=deck%tangent_modulus(m), &
                                               hardening_mixing=deck%hardening_mixing(m)))
    case ('j2_radial')
      allocate (material, source=j2_radial_material_t(young=deck%young(m), poisson=deck%poisson(m), &
                                                      yield_stress=deck%yield_stress(m), &
                                                      tangent_modulus=deck%tangent_modulus(m), &
                                                      hardening_mixing=deck%hardening_mixing(m)))
    case ('j2_rate')
      allocate (material, source=j2_rate_material_t(young=deck%young(m), poisson=deck%poisson(m), &
                                                    yield_stress=deck%yield_stress(m), &
                                                    tangent_modulus=deck%tangent_modulus(m), &
                                                    hardening_mixing=deck%hardening_mixing(m), &
                                                    rate_c=deck%rate_c(m), rate_p=deck%rate_p(m)))
    case ('piecewise_linear', 'piecewise_linear_rate')
      allocate (material, source=piecewise_linear_of(deck, m))
    end select
    if (allocated(material)) then
      if (material%state_width() > max_state_words) deallocate (material)
    end if
  end subroutine material_from_deck

  !> A piecewise_linear(_rate) material: its hardening curve (none: the bilinear law of
  !> yield_stress and tangent_modulus, two points extrapolated along their line) and its rate law
  !> (Cowper-Symonds for piecewise_linear_rate; else its rate curve, if any).
  function piecewise_linear_of(deck, m) result(material)
    class(deck_fields_t), intent(in) :: deck
    integer, intent(in) :: m
    type(piecewise_linear_material_t) :: material
    real(wp), allocatable :: strain(:), stress(:), rates(:), factors(:)
    real(wp) :: h, rate_c, rate_p
    integer :: law
    if (curve_of(deck%hardening_curve, m) > 0) then
      call curve_points(deck, curve_of(deck%hardening_curve, m), strain, stress)
    else
      h = deck%young(m) * deck%tangent_modulus(m) / (deck%young(m) - deck%tangent_modulus(m))
      strain = [0.0_wp, 1.0_wp]
      stress = [deck%yield_stress(m), deck%yield_stress(m) + h]
    end if
    law = rate_none
    rate_c = 1.0_wp
    rate_p = 1.0_wp
    rates = [0.0_wp]
    factors = [1.0_wp]
    if (enum_name(enum_material_model, deck%material_model(m)) == 'piecewise_linear_rate') then
      law = rate_cowper_symonds
      rate_c = deck%rate_c(m)
      rate_p = deck%rate_p(m)
    else if (curve_of(deck%rate_curve, m) > 0) then
      law = rate_tabulated
      call curve_points(deck, curve_of(deck%rate_curve, m), rates, factors)
    end if
    material = piecewise_linear_from_curve(deck%young(m), deck%poisson(m), strain, stress, law, rate_c, rate_p, &
                                           rates, factors)
  end function piecewise_linear_of

  !> The 1-based curve that an optional curve field names for material m (0: none, or no field)
  pure integer function curve_of(field, m) result(curve)
    integer, allocatable, intent(in) :: field(:)
    integer, intent(in) :: m
    curve = 0
    if (allocated(field)) curve = field(m)
  end function curve_of

  !> The points of curve c (1-based) of the deck: its times as x, its values as y.
  subroutine curve_points(deck, c, x, y)
    class(deck_fields_t), intent(in) :: deck
    integer, intent(in) :: c
    real(wp), allocatable, intent(out) :: x(:), y(:)
    integer :: first, last
    first = deck%curve_first_point(c)
    last = deck%n_curve_points
    if (c < deck%n_curves) last = deck%curve_first_point(c + 1) - 1
    x = deck%curve_time(first:last)
    y = deck%curve_value(first:last)
  end subroutine curve_points

end module material_factory
