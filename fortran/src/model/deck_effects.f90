!> Which effects a deck declares, and the scene's switches applied to it (issue 13): an effect
!> the scene switches off is taken out of the deck before set-up (a J2 material becomes elastic,
!> friction coefficients become 0, the loads go), so the solver never builds or calls it. The one
!> place that decides what a deck switches on; everything else reads the table in results.h5.
module deck_effects
  use paradyn_kinds, only: wp
  use paradyn_schema, only: n_effects, material_is_plastic, material_is_rigid, material_elastic, &
                            effect_time_integration, effect_mass_damping, effect_fixed_boundaries, &
                            effect_elastic_shells, effect_plastic_shells, effect_hourglass, effect_contact, &
                            effect_friction, effect_gravity
  use model_deck, only: deck_t, deck_gravity
  use deck_fields, only: declare_by_rows, drop_rows
  use effect_table, only: effect_table_t
  implicit none
  private
  public :: declared_effects, effects_of_deck

contains

  !> The effects the deck declares (schema/effects.toml declared_by), whether switched off or not.
  pure function declared_effects(deck) result(declared)
    type(deck_t), intent(in) :: deck
    logical :: declared(n_effects)
    integer, allocatable :: part_model(:)
    declared = .false.
    part_model = deck%material_model(deck%part_material)
    call declare_by_rows(deck, declared)   ! the effects declared by the rows of their tables
    declared(effect_time_integration) = .true.
    declared(effect_mass_damping) = deck%mass_damping > 0.0_wp
    declared(effect_fixed_boundaries) = deck%any_fixed   ! over the whole mesh (deck_checks)
    ! a rigid part's elements compute nothing (rigid/): neither shells nor hourglass forces
    declared(effect_elastic_shells) = any(.not. material_is_plastic(part_model) .and. &
                                          .not. material_is_rigid(part_model))
    declared(effect_plastic_shells) = any(material_is_plastic(part_model))
    declared(effect_hourglass) = any(deck%hourglass_coefficient > 0.0_wp .and. .not. material_is_rigid(part_model))
    if (deck%n_contacts > 0) declared(effect_friction) = any(deck%contact_static_friction > 0.0_wp) .or. &
                                                          any(deck%contact_dynamic_friction > 0.0_wp)
    declared(effect_gravity) = any(deck_gravity(deck) /= 0.0_wp)
  end function declared_effects

  !> The effect table of the deck (what it declares, what runs), and the deck with the effects
  !> the scene switched off taken out.
  subroutine effects_of_deck(deck, table)
    type(deck_t), intent(inout) :: deck
    type(effect_table_t), intent(out) :: table
    table%declared = declared_effects(deck)
    table%running = table%declared .and. deck%effect_on
    associate (off => table%declared .and. .not. table%running)
      call drop_rows(deck, off)   ! the effects declared by rows: their rows go
      if (off(effect_mass_damping)) deck%mass_damping = 0.0_wp
      if (off(effect_plastic_shells)) then
        where (material_is_plastic(deck%material_model)) deck%material_model = material_elastic
        table%declared(effect_elastic_shells) = .true.   ! those parts now run as elastic shells
        table%running(effect_elastic_shells) = .true.
      end if
      if (off(effect_hourglass)) deck%hourglass_coefficient = 0.0_wp
      if (off(effect_contact)) table%running(effect_friction) = .false.
      if (off(effect_friction)) then
        deck%contact_static_friction = 0.0_wp
        deck%contact_dynamic_friction = 0.0_wp
      end if
      if (off(effect_gravity)) then
        deck%gravity_x = 0.0_wp
        deck%gravity_y = 0.0_wp
        deck%gravity_z = 0.0_wp
      end if
    end associate
  end subroutine effects_of_deck

end module deck_effects
