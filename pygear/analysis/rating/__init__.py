"""Will it last?  Gear rating to ISO 6336:2019 method B, service life under a duty cycle
(ISO 6336-6) and rolling bearing life (ISO 281:2007).

- :mod:`.factors`: every influence factor of ISO 6336-1/-2/-3 as a plain function;
- :mod:`.tooth_form`: Y_F and Y_S by method B, external and internal gears;
- :mod:`.gear_rating`: one mesh rated, factor by factor, with clause and source;
- :mod:`.gearbox_rating`: the torque through a case's stages, every mesh rated, the
  duty-cycle damage and the bearings' lives; K_v per mesh from the dynamic model
  (:func:`~.gearbox_rating.model_dynamic_factors`) or from outside
  (``rate_gearbox(..., dynamic_factors=...)``), K_gamma from planet forces
  (:func:`~.gearbox_rating.load_sharing_from_forces`);
- :mod:`.load_sharing`: K_gamma from the case's static model with planet position
  errors (``Rating(planet_position_errors=...)``);
- :mod:`.duty`: rainflow counting (ASTM E1049-85), S-N curves, Palmgren-Miner;
- :mod:`.run_damage`: the damage of a run's mesh forces from their rainflow matrices;
- :mod:`.duty_files`: what a duty-cycle file holds (a run, its streamed reductions, a
  batch's spectrum, an OpenFAST record) as the rating takes it;
- :mod:`.bearing_life`: L10, P, P_m, a_ISO;
- :mod:`.dataset`: the result as an ``xarray.Dataset``.
"""
