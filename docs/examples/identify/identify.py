import matplotlib.pyplot as plt
import pandas as pd
import tether

data = pd.read_csv("docs/examples/identify/recording.csv")
guess = tether.Scene.load("docs/examples/identify/guess.json")
result = tether.identify(guess, data, "/bodies/1/mass", segments=6)
print(result["parameters"], result["standard_deviation"], result["evaluations"])
run = guess.set("/bodies/1/mass", result["parameters"]["/bodies/1/mass"]).simulate()
axes = data.plot(x="t", subplots=True, style=".", markersize=3, figsize=(8, 9), legend=False, xlabel="t (s)")
for ax, column in zip(axes, data.columns[1:]):
    ax.plot(run.t, run[column], "k", linewidth=1)
    ax.set_ylabel(column + " (m)")  # positions
axes[0].legend(["recording.csv", "simulated with the estimate"], loc="lower right", fontsize=8)
plt.savefig("fit.png", bbox_inches="tight")
