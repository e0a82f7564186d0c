"""Print docs/logs.md's held-out table: the bundled Hinsdale trials replayed with the published-parameter and the
fitted model, beside the authors' own simulation (uvms.replays.hinsdale)."""

import uvms
from uvms.replays.hinsdale import held_out_scores, markdown_table

published = held_out_scores(uvms.load_model("hinsdale_bluerov2_alpha5"))
fitted = held_out_scores(uvms.load_model("hinsdale_bluerov2_alpha5_fit"))
print(markdown_table(published, fitted))
print(f"fit beats the authors on {sum(s.beats_authors for s in fitted)} of {len(fitted)} trials (attitude RMSE), "
      f"pitch alone on {sum(s.pitch < s.authors_pitch for s in fitted)}, roll alone on "
      f"{sum(s.roll < s.authors_roll for s in fitted)}")
